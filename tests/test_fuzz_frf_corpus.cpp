// Regression run of the FRF fuzz target (fuzz/fuzz_frf.cpp) over its corpus
// fuzz/corpus/frf/: every file must be read into valid tables or refused with
// an InputError by each reader (CSV, tab, UFF 58); the target aborts
// otherwise, failing the test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

std::vector<std::filesystem::path> corpus(const std::string& name) {
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(std::string(CHATTER_SOURCE_DIR) + "/fuzz/corpus/" + name))
    if (e.is_regular_file()) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

TEST(FuzzCorpus, FrfReadersSurviveEveryCorpusFile) {
  const auto files = corpus("frf");
  ASSERT_GE(files.size(), 40u);  // the seeds of tests/corpus/frf/ at least
  for (const auto& f : files) {
    SCOPED_TRACE(f.string());
    std::ifstream in(f, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), {});
    EXPECT_EQ(LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()), 0);
  }
}

}  // namespace
