// Regression run of the program's own readers (fuzz/fuzz_program.cpp) over
// its corpus fuzz/corpus/program/: JOB.toml (load_job) and the interpreter's
// canonical-call log (parse_canon_log) must be read into a job and a
// toolpath obeying their rules, or refused with an InputError; the target
// aborts otherwise, failing the test.
#include "fuzz_replay.hpp"

namespace {

// At least the seeds committed with the target.
TEST(FuzzCorpus, ProgramReadersSurviveEveryCorpusFile) { chatter::test::replay_fuzz_corpus("program", 5u); }

}  // namespace
