// Regression run of the operations fuzz target (fuzz/fuzz_operations.cpp) over its corpus
// fuzz/corpus/operations/: every file must be parsed into valid rows (for a
// turning and a milling process) or refused with an InputError; the target aborts
// otherwise, failing the test.
#include "fuzz_replay.hpp"

namespace {

// At least examples/operations/ and the broken seeds.
TEST(FuzzCorpus, OperationsReaderSurvivesEveryCorpusFile) { chatter::test::replay_fuzz_corpus("operations", 10u); }

}  // namespace
