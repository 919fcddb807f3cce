// tests/installation <-> installation/installation.h: the version line and where the data
// directory is found (docs/install.md).
#include "installation.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "test_paths.h"

namespace {
namespace fs = std::filesystem;
using swum::installation::find_data_dir;

// A fresh folder under the system's temporary folder, removed at the end of the test.
class TempTree {
 public:
  TempTree()
      : root_(fs::temp_directory_path() / ("swum-installation-" + std::to_string(::getpid()) + "-" +
                                           ::testing::UnitTest::GetInstance()->current_test_info()->name())) {
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  ~TempTree() { fs::remove_all(root_); }
  const fs::path& root() const { return root_; }
  // Makes DIR/li2019.toml; returns DIR.
  fs::path data_dir_at(const fs::path& relative) const {
    const fs::path dir = root_ / relative;
    fs::create_directories(dir);
    std::ofstream(dir / "li2019.toml") << "# a motor\n";
    return dir;
  }

 private:
  fs::path root_;
};

fs::path this_executable() { return fs::read_symlink("/proc/self/exe"); }

TEST(Installation, VersionLineNamesTheProgramAndTheProjectVersion) {
  const std::string line = swum::installation::version_line("swum");
  EXPECT_EQ(line.rfind("swum " + std::string(swum::installation::version()), 0), 0u) << line;
  EXPECT_EQ(line.find('\n'), std::string::npos);
  // CMake's project(VERSION): three whole numbers.
  const std::string v(swum::installation::version());
  EXPECT_EQ(std::count(v.begin(), v.end(), '.'), 2) << v;
}

TEST(Installation, ExplicitDataDirWins) {
  TempTree t;
  const fs::path dir = t.data_dir_at("mine");
  std::string tried;
  EXPECT_EQ(find_data_dir(this_executable(), dir.c_str(), tried), dir);
}

TEST(Installation, ExplicitDataDirWithoutTheMotorIsAnErrorNotAFallback) {
  TempTree t;
  std::string tried;
  // Even though this test binary would otherwise find the checkout's config/.
  EXPECT_EQ(find_data_dir(this_executable(), t.root().c_str(), tried), std::nullopt);
  EXPECT_EQ(tried, "$SWUM_DATA_DIR=" + t.root().string() + " (no li2019.toml there)");
}

TEST(Installation, AnInstallationFindsShareBesideBinWhateverItsPrefix) {
  TempTree t;
  const fs::path data = t.data_dir_at("opt/prefix/share/swum-hil");
  std::string tried;
  EXPECT_EQ(find_data_dir(t.root() / "opt/prefix/bin/swum-emu", nullptr, tried), data);
  EXPECT_EQ(find_data_dir(t.root() / "opt/prefix/bin/swum-emu", "", tried), data);  // empty = unset
}

TEST(Installation, AnInstalledBinaryNeverReachesIntoTheCheckout) {
  TempTree t;  // bin/ without share/swum-hil, outside the build folder
  std::string tried;
  EXPECT_EQ(find_data_dir(t.root() / "usr/bin/swum", nullptr, tried), std::nullopt);
  EXPECT_EQ(tried, (t.root() / "usr/share/swum-hil").string());
}

TEST(Installation, ABuildOfTheCheckoutReadsItsConfigFolder) {
  std::string tried;
  const auto dir = find_data_dir(this_executable(), nullptr, tried);
  ASSERT_TRUE(dir.has_value()) << tried;
  EXPECT_EQ(*dir, fs::path(swum::test::source_path("config")).lexically_normal());
  EXPECT_EQ(swum::installation::default_config_path(), *dir / "li2019.toml");
}

}  // namespace
