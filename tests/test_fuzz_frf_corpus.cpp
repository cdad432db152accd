// Regression run of the FRF fuzz target (fuzz/fuzz_frf.cpp) over its corpus
// fuzz/corpus/frf/: every file must be read into valid tables or refused with
// an InputError by each reader (CSV, tab, UFF 58); the target aborts
// otherwise, failing the test.
#include "fuzz_replay.hpp"

namespace {

// At least the seeds of tests/corpus/frf/.
TEST(FuzzCorpus, FrfReadersSurviveEveryCorpusFile) { chatter::test::replay_fuzz_corpus("frf", 40u); }

}  // namespace
