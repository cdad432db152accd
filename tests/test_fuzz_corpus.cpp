// Regression run of the fuzz targets over their corpora: every file must be
// either accepted with valid values or refused with an InputError (the target
// aborts otherwise, failing the test).
#include "fuzz_replay.hpp"

namespace {

TEST(FuzzCorpus, ConfigLoaderSurvivesEveryCorpusFile) { chatter::test::replay_fuzz_corpus("config", 8u); }

}  // namespace
