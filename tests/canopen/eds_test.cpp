// The compiled dictionary (swum_eds_objects(), generated from config/swum.eds by tools/eds-to-cpp)
// and the EDS agree object by object, read here by a small reader of its own (not the generator):
// name, type, access, PDO mapping, default and limits of every sub-index, both ways. And the
// tables of docs/canopen.md list the same objects with the same type, access, PDO flag, plain
// defaults and ranges, so that docs, EDS and code cannot drift apart.
#include <gtest/gtest.h>

#include <cctype>
#include <cstdint>
#include <fstream>
#include <map>
#include <optional>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "object_dictionary.h"
#include "test_paths.h"

namespace swum::canopen {
namespace {

using Section = std::map<std::string, std::string>;  // key (lower case) -> value

std::string lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

std::string trim(const std::string& text) {
  const auto first = text.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(" \t\r") - first + 1);
}

// An INI file as CiA 306 writes it: [section], key=value, ';' comments. Section names upper case.
std::map<std::string, Section> read_ini(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in) << path;
  std::map<std::string, Section> sections;
  std::string line, current;
  while (std::getline(in, line)) {
    line = trim(line);
    if (line.empty() || line[0] == ';') continue;
    if (line.front() == '[' && line.back() == ']') {
      current = line.substr(1, line.size() - 2);
      for (char& c : current) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
      EXPECT_EQ(sections.count(current), 0u) << "[" << current << "] twice";
      sections[current];
      continue;
    }
    const auto equals = line.find('=');
    EXPECT_NE(equals, std::string::npos) << line;
    if (equals == std::string::npos) continue;
    sections[current][lower(trim(line.substr(0, equals)))] = trim(line.substr(equals + 1));
  }
  return sections;
}

std::int64_t number(const std::string& text) {
  std::size_t used = 0;
  const std::int64_t value = std::stoll(text, &used, 0);
  EXPECT_EQ(used, text.size()) << "'" << text << "' is not a whole number";
  return value;
}

std::string hex(std::uint16_t index, std::uint8_t sub) {
  char text[24];
  std::snprintf(text, sizeof text, "0x%04X sub %u", index, static_cast<unsigned>(sub));
  return text;
}

// What the EDS says of one sub-index, in the compiled table's terms.
struct EdsEntry {
  std::string name;
  std::uint16_t type;
  std::string access;
  bool pdo;
  std::string default_text;
  std::optional<std::pair<std::int64_t, std::int64_t>> limits;
};

EdsEntry entry_of(const Section& s) {
  EdsEntry e{s.at("parametername"),     static_cast<std::uint16_t>(number(s.at("datatype"))),
             lower(s.at("accesstype")), s.at("pdomapping") == "1",
             s.at("defaultvalue"),      std::nullopt};
  if (s.count("lowlimit")) e.limits = std::make_pair(number(s.at("lowlimit")), number(s.at("highlimit")));
  return e;
}

class Eds : public ::testing::Test {
 protected:
  void SetUp() override {
    ini = read_ini(test::source_path("config/swum.eds"));
    const std::regex object_name("^[0-9A-F]{4}$");
    for (const auto& [name, section] : ini) {
      if (!std::regex_match(name, object_name)) continue;
      const auto index = static_cast<std::uint16_t>(std::stoul(name, nullptr, 16));
      const std::int64_t object_type = number(section.at("objecttype"));
      if (object_type == 0x7) {
        entries[{index, 0}] = entry_of(section);
        continue;
      }
      int subs = 0;
      for (int sub = 0; sub < 256; ++sub) {
        char sub_name[16];
        std::snprintf(sub_name, sizeof sub_name, "%sSUB%X", name.c_str(), static_cast<unsigned>(sub));
        if (!ini.count(sub_name)) continue;
        entries[{index, static_cast<std::uint8_t>(sub)}] = entry_of(ini.at(sub_name));
        ++subs;
      }
      EXPECT_EQ(number(section.at("subnumber")), subs) << name;
    }
  }

  std::map<std::string, Section> ini;
  std::map<std::pair<std::uint16_t, std::uint8_t>, EdsEntry> entries;
};

TEST_F(Eds, EveryCompiledObjectIsInTheEdsAsDescribed) {
  const std::map<std::string, Access> accesses{{"ro", Access::ro},  {"wo", Access::wo},  {"rw", Access::rw},
                                               {"rwr", Access::rw}, {"rww", Access::rw}, {"const", Access::const_}};
  ASSERT_FALSE(swum_eds_objects().empty());
  for (const ObjectDescription& d : swum_eds_objects()) {
    const std::string where = hex(d.index, d.sub);
    const auto found = entries.find({d.index, d.sub});
    ASSERT_NE(found, entries.end()) << where << " is compiled but not in config/swum.eds";
    const EdsEntry& e = found->second;
    EXPECT_EQ(d.name, e.name) << where;
    EXPECT_EQ(static_cast<std::uint16_t>(d.type), e.type) << where;
    EXPECT_EQ(d.access, accesses.at(e.access)) << where;
    EXPECT_EQ(d.pdo_mappable, e.pdo) << where;
    if (d.type == DataType::visible_string) {
      ASSERT_NE(d.default_string, nullptr) << where;
      EXPECT_EQ(d.default_string, e.default_text) << where;
    } else {
      const std::string prefix = "$NODEID+";
      const bool plus_node = e.default_text.rfind(prefix, 0) == 0;
      EXPECT_EQ(d.default_plus_node_id, plus_node) << where;
      EXPECT_EQ(d.default_value, number(plus_node ? e.default_text.substr(prefix.size()) : e.default_text)) << where;
    }
    EXPECT_EQ(d.has_limits, e.limits.has_value()) << where;
    if (e.limits) {
      EXPECT_EQ(d.low_limit, e.limits->first) << where;
      EXPECT_EQ(d.high_limit, e.limits->second) << where;
    }
  }
}

TEST_F(Eds, EveryEdsObjectIsCompiled) {
  ASSERT_GT(entries.size(), 100u);
  ObjectDictionary od(swum_eds_objects(), 1);
  for (const auto& [key, entry] : entries)
    EXPECT_TRUE(od.find(key.first, key.second))
        << hex(key.first, key.second) << " (" << entry.name << ") is not compiled";
  EXPECT_EQ(entries.size(), swum_eds_objects().size());
}

TEST_F(Eds, ObjectListsNameEachObjectSectionOnce) {
  std::set<std::uint16_t> sections;
  for (const auto& [key, entry] : entries) sections.insert(key.first);
  std::multiset<std::uint16_t> listed;
  for (const char* list : {"MANDATORYOBJECTS", "OPTIONALOBJECTS", "MANUFACTUREROBJECTS"}) {
    const Section& s = ini.at(list);
    const std::int64_t count = number(s.at("supportedobjects"));
    EXPECT_EQ(static_cast<std::int64_t>(s.size()), count + 1) << list;
    for (std::int64_t n = 1; n <= count; ++n) {
      const auto index = static_cast<std::uint16_t>(number(s.at(std::to_string(n))));
      listed.insert(index);
      const bool manufacturer = index >= 0x2000 && index <= 0x5FFF;
      EXPECT_EQ(manufacturer, std::string(list) == "MANUFACTUREROBJECTS") << list << " " << n;
    }
  }
  EXPECT_EQ(std::set<std::uint16_t>(listed.begin(), listed.end()), sections);
  EXPECT_EQ(listed.size(), sections.size());  // none twice
  const Section& mandatory = ini.at("MANDATORYOBJECTS");
  EXPECT_EQ(mandatory.at("1"), "0x1000");
  EXPECT_EQ(mandatory.at("2"), "0x1001");
  EXPECT_EQ(mandatory.at("3"), "0x1018");
}

TEST_F(Eds, DeviceInfoAgreesWithTheIdentityAndThePdos) {
  const Section& info = ini.at("DEVICEINFO");
  ObjectDictionary od(swum_eds_objects(), 1);
  EXPECT_EQ(number(info.at("vendornumber")), od.u32(od.slot(0x1018, 1)));
  EXPECT_EQ(number(info.at("productnumber")), od.u32(od.slot(0x1018, 2)));
  EXPECT_EQ(number(info.at("revisionnumber")), od.u32(od.slot(0x1018, 3)));
  int rpdos = 0, tpdos = 0;
  for (std::uint16_t index = 0x1400; index <= 0x15FF; ++index) rpdos += od.has_index(index) ? 1 : 0;
  for (std::uint16_t index = 0x1800; index <= 0x19FF; ++index) tpdos += od.has_index(index) ? 1 : 0;
  EXPECT_EQ(number(info.at("nrofrxpdo")), rpdos);
  EXPECT_EQ(number(info.at("nroftxpdo")), tpdos);
  EXPECT_EQ(info.at("simplebootupslave"), "1");
  EXPECT_EQ(info.at("granularity"), "8");
  EXPECT_EQ(info.at("lss_supported"), "0");
  for (int dummy = 1; dummy <= 7; ++dummy) EXPECT_EQ(ini.at("DUMMYUSAGE").at("dummy000" + std::to_string(dummy)), "0");
}

TEST_F(Eds, SoftwareVersionAndRevisionAreTheProjectVersion) {
  std::ifstream cmake(test::source_path("CMakeLists.txt"));
  std::stringstream text;
  text << cmake.rdbuf();
  std::smatch m;
  const std::string content = text.str();
  ASSERT_TRUE(std::regex_search(content, m, std::regex(R"(project\(\s*\w+\s+VERSION\s+(\d+)\.(\d+)\.(\d+))")));
  ObjectDictionary od(swum_eds_objects(), 1);
  EXPECT_EQ(od.string(od.slot(0x100A, 0)), m[1].str() + "." + m[2].str() + "." + m[3].str());
  EXPECT_EQ(od.u32(od.slot(0x1018, 3)), (std::stoul(m[1].str()) << 16) | std::stoul(m[2].str()));
}

// docs/canopen.md: the rows of its three object tables.
struct DocRow {
  std::vector<std::uint16_t> indexes;
  std::string sub;  // "" in the manufacturer table (sub 0)
  std::string type, access, pdo, default_text, range;
};

std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  for (std::size_t i = 1; i < line.size(); ++i) {
    if (line[i] == '|' && line[i - 1] != '\\') {
      out.push_back(trim(cell));
      cell.clear();
    } else {
      cell += line[i];
    }
  }
  return out;
}

std::vector<DocRow> doc_rows() {
  std::ifstream in(test::source_path("docs/canopen.md"));
  EXPECT_TRUE(in);
  std::vector<DocRow> rows;
  std::vector<std::string> header;
  std::vector<std::uint16_t> last_indexes;
  std::string line;
  const std::regex index_cell(R"(^0x([0-9A-F]{4})(?:-0x([0-9A-F]{4}))?$)");
  while (std::getline(in, line)) {
    if (line.rfind("|", 0) != 0) {
      header.clear();
      continue;
    }
    const auto c = cells(line);
    if (header.empty()) {
      header = c;
      continue;
    }
    if (c.empty() || c[0].rfind("---", 0) == 0 || header[0] != "index") continue;
    std::map<std::string, std::string> by_name;
    for (std::size_t i = 0; i < c.size() && i < header.size(); ++i) by_name[header[i]] = c[i];
    DocRow row;
    std::smatch m;
    if (std::regex_match(c[0], m, index_cell)) {
      const auto first = static_cast<std::uint16_t>(std::stoul(m[1].str(), nullptr, 16));
      const auto last = m[2].matched ? static_cast<std::uint16_t>(std::stoul(m[2].str(), nullptr, 16)) : first;
      for (std::uint32_t i = first; i <= last; ++i) row.indexes.push_back(static_cast<std::uint16_t>(i));
      last_indexes = row.indexes;
    } else {
      EXPECT_EQ(c[0], "") << line;
      row.indexes = last_indexes;  // a further sub-index of the row above
    }
    row.sub = by_name.count("sub") ? by_name["sub"] : "0";
    row.type = by_name["type"];
    row.access = by_name["access"];
    row.pdo = by_name["PDO"];
    row.default_text = by_name["default"];
    row.range = by_name["range"];
    rows.push_back(row);
  }
  return rows;
}

TEST(EdsAndDocs, TheDocsTablesListTheSameObjects) {
  const auto rows = doc_rows();
  ASSERT_GT(rows.size(), 50u);
  std::set<std::uint16_t> documented, compiled;
  for (const DocRow& row : rows) documented.insert(row.indexes.begin(), row.indexes.end());
  for (const ObjectDescription& d : swum_eds_objects()) compiled.insert(d.index);
  for (std::uint16_t index : compiled)
    EXPECT_TRUE(documented.count(index)) << hex(index, 0) << " is not in docs/canopen.md";
  for (std::uint16_t index : documented)
    EXPECT_TRUE(compiled.count(index)) << hex(index, 0) << " is only in docs/canopen.md";
}

TEST(EdsAndDocs, TheDocsRowsOfOneSubIndexAgreeWithTheDictionary) {
  const std::map<std::string, DataType> types{{"BOOLEAN", DataType::boolean},
                                              {"INTEGER8", DataType::integer8},
                                              {"INTEGER16", DataType::integer16},
                                              {"INTEGER32", DataType::integer32},
                                              {"UNSIGNED8", DataType::unsigned8},
                                              {"UNSIGNED16", DataType::unsigned16},
                                              {"UNSIGNED32", DataType::unsigned32},
                                              {"REAL32", DataType::real32},
                                              {"VISIBLE_STRING", DataType::visible_string}};
  const std::map<std::string, Access> accesses{{"ro", Access::ro}, {"rw", Access::rw}, {"const", Access::const_}};
  const std::regex plain_number(R"(^-?(0x[0-9A-Fa-f]+|[0-9]+)$)");
  const std::regex range(R"(^(-?[0-9]+)\.\.(-?[0-9]+)$)");
  ObjectDictionary od(swum_eds_objects(), 1);
  int checked = 0;
  for (const DocRow& row : doc_rows()) {
    if (row.sub.empty() || row.sub.find('-') != std::string::npos || !types.count(row.type)) continue;
    const auto sub = static_cast<std::uint8_t>(std::stoul(row.sub));
    for (std::uint16_t index : row.indexes) {
      const auto slot = od.find(index, sub);
      ASSERT_TRUE(slot) << hex(index, sub);
      const ObjectDescription& d = od.description(*slot);
      const std::string where = hex(index, sub);
      EXPECT_EQ(d.type, types.at(row.type)) << where;
      const std::string access = row.access.substr(0, row.access.find(' '));
      ASSERT_TRUE(accesses.count(access)) << where << ": '" << row.access << "'";
      EXPECT_EQ(d.access, accesses.at(access)) << where;
      EXPECT_EQ(d.pdo_mappable, row.pdo == "yes") << where << ": PDO '" << row.pdo << "'";
      if (std::regex_match(row.default_text, plain_number)) {
        EXPECT_FALSE(d.default_plus_node_id) << where;
        EXPECT_EQ(d.default_value, number(row.default_text)) << where;
      }
      std::smatch m;
      if (std::regex_match(row.range, m, range)) {
        EXPECT_TRUE(d.has_limits) << where;
        EXPECT_EQ(d.low_limit, number(m[1].str())) << where;
        EXPECT_EQ(d.high_limit, number(m[2].str())) << where;
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 60);
}

}  // namespace
}  // namespace swum::canopen
