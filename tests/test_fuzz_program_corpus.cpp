// Regression run of the program's own readers (fuzz/fuzz_program.cpp) over
// its corpus fuzz/corpus/program/: JOB.toml (load_job) and the interpreter's
// canonical-call log (parse_canon_log) must be read into a job and a
// toolpath obeying their rules, or refused with an InputError; the target
// aborts otherwise, failing the test.
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

TEST(FuzzCorpus, ProgramReadersSurviveEveryCorpusFile) {
  const auto files = corpus("shop");
  ASSERT_GE(files.size(), 5u);  // the seeds committed with the target at least
  for (const auto& f : files) {
    SCOPED_TRACE(f.string());
    std::ifstream in(f, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), {});
    EXPECT_EQ(LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()), 0);
  }
}

}  // namespace
