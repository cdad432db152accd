// Regression run of the logged-test readers (fuzz/fuzz_logs.cpp) over its
// corpus fuzz/corpus/logs/: every file must be read as a grinding tests table
// (and fitted: mechanistic, poly11) and as an adapt measurement log into data
// obeying the readers' rules, or be refused with an InputError; the target
// aborts otherwise, failing the test.
#include "fuzz_replay.hpp"

namespace {

// At least the seeds committed with the target.
TEST(FuzzCorpus, LogReadersSurviveEveryCorpusFile) { chatter::test::replay_fuzz_corpus("logs", 7u); }

}  // namespace
