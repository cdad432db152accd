// The regression run of a fuzz target over its corpus fuzz/corpus/<name>/,
// shared by the tests/test_fuzz_*_corpus.cpp files (each links one target's
// entry point): every file must be accepted with valid values or refused
// with an InputError; the target aborts otherwise, failing the test.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace chatter::test {

/// The files of fuzz/corpus/<name>/, sorted.
inline std::vector<std::filesystem::path> fuzz_corpus(const std::string& name) {
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(std::string(CHATTER_SOURCE_DIR) + "/fuzz/corpus/" + name))
    if (e.is_regular_file()) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

/// Runs the linked target on every file of the corpus (at least `at_least`
/// files: the seeds committed with the target).
inline void replay_fuzz_corpus(const std::string& name, std::size_t at_least) {
  const auto files = fuzz_corpus(name);
  ASSERT_GE(files.size(), at_least);
  for (const auto& f : files) {
    SCOPED_TRACE(f.string());
    std::ifstream in(f, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), {});
    EXPECT_EQ(LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()), 0);
  }
}

}  // namespace chatter::test
