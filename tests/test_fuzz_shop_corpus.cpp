// Regression run of the shop-data readers (fuzz/fuzz_shop.cpp) over its corpus
// fuzz/corpus/shop/: every file must be read (tests table, force series, CSV
// and audio recording) into data obeying the readers' rules, with a finite
// coefficient fit and detection, or be refused with an InputError; the target
// aborts otherwise, failing the test. The crash_* files are the findings of
// docs/reliability.md (a detector peak on a slope, a revolution count
// overflowing int).
#include "fuzz_replay.hpp"

namespace {

// At least the seeds committed with the target.
TEST(FuzzCorpus, ShopReadersSurviveEveryCorpusFile) { chatter::test::replay_fuzz_corpus("shop", 18u); }

}  // namespace
