// A CiA 301 slave's object dictionary (docs/canopen.md): the objects of config/swum.eds (CiA 306),
// compiled into a table at build time (tools/eds-to-cpp), their values, and the rules a master's
// write must pass. Pure: no sockets, clocks or threads; the per-frame calls (find, read, write)
// neither allocate nor throw, and answer with a CiA 301 SDO abort code.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

namespace swum::canopen {

// CiA 301 7.1.6 / CiA 306 DataType codes (the ones the dictionary uses).
// clang-format off
enum class DataType : std::uint16_t { boolean = 0x0001, integer8 = 0x0002, integer16 = 0x0003, integer32 = 0x0004,
  unsigned8 = 0x0005, unsigned16 = 0x0006, unsigned32 = 0x0007, real32 = 0x0008, visible_string = 0x0009 };
// clang-format on
enum class Access : std::uint8_t { ro, wo, rw, const_ };  // EDS AccessType (rww/rwr read as rw)

// Bytes of a value of the type; 0 for visible_string (its length is its text's).
std::size_t size_of(DataType type);

// One sub-index as config/swum.eds describes it.
struct ObjectDescription {
  std::uint16_t index;
  std::uint8_t sub;
  const char* name;
  DataType type;
  Access access;
  bool pdo_mappable;
  std::int64_t default_value;
  bool default_plus_node_id;   // EDS DefaultValue=$NODEID+...: the node id is added at load
  const char* default_string;  // visible_string: the text (nullptr otherwise)
  bool has_limits;
  std::int64_t low_limit, high_limit;
};

// The table generated from config/swum.eds, sorted by (index, sub).
std::span<const ObjectDescription> swum_eds_objects();

// CiA 301 SDO abort codes (7.2.4.3.17), the ones this slave uses.
// clang-format off
enum class SdoAbort : std::uint32_t { none = 0, toggle_bit = 0x05030000, timeout = 0x05040000,
  bad_command = 0x05040001, out_of_memory = 0x05040005, unsupported_access = 0x06010000, write_only = 0x06010001,
  read_only = 0x06010002, no_object = 0x06020000, not_mappable = 0x06040041, pdo_too_long = 0x06040042,
  general_incompatibility = 0x06040043, length_mismatch = 0x06070010, length_too_high = 0x06070012,
  length_too_low = 0x06070013, no_sub_index = 0x06090011, value_range = 0x06090030, value_too_high = 0x06090031,
  value_too_low = 0x06090032, general = 0x08000000, state = 0x08000022 };
// clang-format on
// CiA 301's text of the code, for logs and test messages.
const char* describe(SdoAbort code);

// What the application adds to a write: a veto (e.g. 0x6060 only modes 0, 3, -1) and a notice
// after it. Called on the per-frame path: neither may throw or block.
class WriteObserver {
 public:
  virtual SdoAbort check(std::size_t /*slot*/, std::uint32_t /*raw*/) { return SdoAbort::none; }  // before
  virtual void written(std::size_t /*slot*/) {}                                                   // after

 protected:
  ~WriteObserver() = default;
};

class ObjectDictionary {
 public:
  // Throws std::invalid_argument when the table is not sorted and unique, a default or limit does
  // not fit its type, or the node id is outside 1..127.
  ObjectDictionary(std::span<const ObjectDescription> objects, std::uint8_t node_id);

  // Load-time binding of an object the application uses: throws std::out_of_range if absent.
  [[nodiscard]] std::size_t slot(std::uint16_t index, std::uint8_t sub) const;
  // Binary search, no allocation.
  [[nodiscard]] std::optional<std::size_t> find(std::uint16_t index, std::uint8_t sub) const;
  [[nodiscard]] bool has_index(std::uint16_t index) const;
  [[nodiscard]] const ObjectDescription& description(std::size_t slot) const;
  [[nodiscard]] std::size_t size() const;
  [[nodiscard]] std::uint8_t node_id() const { return node_id_; }

  [[nodiscard]] std::uint32_t u32(std::size_t slot) const;        // raw, zero-extended
  [[nodiscard]] std::int32_t i32(std::size_t slot) const;         // sign-extended per type
  [[nodiscard]] std::string_view string(std::size_t slot) const;  // visible_string
  // The application's side: no access check, no observer; the value is cut to the type's size.
  void set(std::size_t slot, std::uint32_t raw);

  // A master's write (SDO download, RPDO): access, length (exact for numbers), limits, the CiA
  // 301 rules of the communication objects the dictionary owns (0x1003, 0x1005, 0x1014, 0x1016,
  // PDO communication and mapping: docs/canopen.md's table), then the observer's check; on
  // success stores, calls written(), returns none. A refused write changes nothing.
  SdoAbort write(std::size_t slot, std::span<const std::uint8_t> bytes);
  // A master's read (SDO upload): the value's bytes little-endian into out (numbers:
  // size_of(type) bytes; a string of at most 4 bytes, a longer one length_too_high: see
  // read_string); write_only -> abort.
  SdoAbort read(std::size_t slot, std::span<std::uint8_t, 4> out, std::size_t& length) const;
  // The whole text of a readable visible_string (a segmented upload's source): empty + abort
  // when the object is not a readable string.
  SdoAbort read_string(std::size_t slot, std::string_view& text) const;

  void set_observer(WriteObserver* observer);
  void reset_communication();  // defaults of 0x1000-0x1FFF (NMT reset communication)
  void reset_application();    // defaults of 0x2000-0x9FFF (NMT reset node does both)

 private:
  [[nodiscard]] std::uint32_t default_raw(std::size_t slot) const;
  void reset_range(std::uint16_t first, std::uint16_t last);
  SdoAbort check_communication_rules(std::size_t slot, std::uint32_t raw) const;
  SdoAbort check_pdo_mapping(std::uint16_t mapping_index, std::uint8_t count) const;
  SdoAbort check_mapping_entry(std::uint32_t entry, bool receive) const;
  [[nodiscard]] std::uint32_t value_at(std::uint16_t index, std::uint8_t sub) const;

  std::span<const ObjectDescription> objects_;
  std::uint8_t node_id_;
  std::vector<std::uint32_t> values_;  // one per slot, raw (zero-extended); sized at construction
  WriteObserver* observer_ = nullptr;
};

}  // namespace swum::canopen
