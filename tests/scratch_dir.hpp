#pragma once
// A scratch folder per test process under the system's temporary folder, removed when
// the program's tests end: scratch(name) is a path in it (its folder created).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

namespace acuity::testing {

inline std::filesystem::path scratch(const std::string& name) {
  const std::filesystem::path p =
      std::filesystem::temp_directory_path() / ("acuity_test_" + std::to_string(::getpid())) / name;
  std::filesystem::create_directories(p.parent_path());
  return p;
}

struct ScratchCleanup : ::testing::Environment {
  void TearDown() override { std::filesystem::remove_all(scratch("x").parent_path()); }
};
inline const auto* const kScratchCleanup = ::testing::AddGlobalTestEnvironment(new ScratchCleanup);

}  // namespace acuity::testing
