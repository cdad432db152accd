// chatter.program: chatter program --json's record (chatter/records/program.hpp)
// as a dict (docs/program.md): an NC program checked block by block.
#include <nlohmann/json.hpp>

#include "bindings.hpp"
#include "chatter/io/job.hpp"
#include "chatter/records/program.hpp"
#include "module.hpp"

namespace chatter_py {

using namespace pybind11::literals;

namespace {

py::dict program(const std::string& path, const std::string& job_path, bool fix_speed, bool fix_feed,
                 std::optional<bool> cache, int threads) {
  const chatter::Job job = chatter::load_job(job_path);
  chatter::ProgramOptions o;
  o.threads = thread_count(threads);
  o.fix_speed = fix_speed;
  o.fix_feed = fix_feed;
  o.cache = cache;
  chatter::ProgramReport r;
  {
    py::gil_scoped_release release;
    r = chatter::run_program(path, job, o);
  }
  return to_python(chatter::program_record(r));
}

}  // namespace

void bind_program(py::module_& m) {
  m.def("program", &program, "path"_a, "config"_a, py::kw_only(), "fix_speed"_a = false, "fix_feed"_a = false,
        "cache"_a = py::none(), "threads"_a = 0,
        "An NC program (G-code, read by LinuxCNC's interpreter) checked block by block against the stock of the "
        "job config: the record of chatter program --json (docs/program.md).");
}

}  // namespace chatter_py
