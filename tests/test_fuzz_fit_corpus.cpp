// Regression run of the modal fit (fuzz/fuzz_fit.cpp) over its corpus fuzz/corpus/fit/:
// every decoded FRF table must give a physical fit with finite numbers or be
// refused with an InputError; the target aborts otherwise, failing the test.
#include "fuzz_replay.hpp"

namespace {

// At least the seeds committed with the target.
TEST(FuzzCorpus, ModalFitSurvivesEveryCorpusFile) { chatter::test::replay_fuzz_corpus("fit", 7u); }

}  // namespace
