// Shared pieces of the Python module `chatter` (pybind11): the Job, the
// solver cache, argument checks with the CLI's defaults and messages, and the
// one converter from a library record (chatter/records.hpp, JSON) to Python
// objects. Each command's bindings live in their own bind_*.cpp
// (python/bindings.hpp); the module is assembled in chatter_module.cpp.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "chatter/error.hpp"
#include "chatter/io/config.hpp"
#include "chatter/lobes.hpp"
#include "chatter/records.hpp"  // SolverRecipe
#include "chatter/records/columns.hpp"
#include "chatter/solvers.hpp"

namespace chatter_py {

namespace py = pybind11;
using chatter::InputError;

// The CLI's defaults (src/cli/cli_common.hpp), kept equal so that the same
// call gives the same table.
constexpr double kDefaultDepthMaxMm = 50.0;
constexpr int kDefaultRpmPoints = 400;
constexpr long long kMaxRpmPoints = 1'000'000;
constexpr long long kMaxSurfacePoints = 4'000'000;  // positions x speeds, as the CLI's surface
constexpr int kDefaultPositionPoints = 21;           // as the CLI's surface
constexpr long long kMaxMonteCarloSolves = 25'000'000;  // samples x speeds, as the CLI's lobes --samples
constexpr int kDefaultDepthPoints = 101;                // as the CLI's --depth-points
constexpr double kDefaultFeedMm = 0.1;         // chatter simulate's feed default
constexpr double kDefaultSimRtol = 1e-7;       // chatter simulate --rtol default
constexpr double kDefaultSpeedTolPct = 2.0;    // chatter check --speed-tolerance-pct default
constexpr const char* kJobOrigin = "<chatter.Job>";


/// A number for messages, as the CLI prints it (6 significant digits).
std::string fmt(double x);

/// A loaded or built config: model, process, sweep defaults. Immutable, so
/// one Job may be used from several Python threads at once.
struct Built;
/// The solvers built for a job, by (method, depth searched, options): the
/// analytic solver's construction (its lobe geometry) costs about 30 times a
/// limit_at, so repeated point() calls reuse it. Solvers are immutable, so
/// the result is bitwise the same as building a new one. At most
/// kMaxCachedSolvers entries (then the cache starts again: no growth).
struct SolverCache {
  std::mutex mutex;
  std::map<std::string, std::shared_ptr<const Built>> solvers;
};
constexpr std::size_t kMaxCachedSolvers = 16;

struct Job {
  std::shared_ptr<const chatter::Config> cfg;
  std::shared_ptr<SolverCache> cache = std::make_shared<SolverCache>();
};


/// A Job from a loaded config; with `strict`, a config with plausibility
/// warnings is refused (InputError naming them).
Job job_from(chatter::Config c, bool strict);
/// The job at a tool position (docs/position.md), through the io layer as
/// the CLI's --position-mm: messages name `position_mm`. No position: the job.
Job at_position(const Job& job, const std::optional<double>& position_mm);

py::object optional_number(const std::optional<double>& x);
py::object optional_int(const std::optional<int>& x);
py::object finite_or_none(double x);

/// What the CLI's build_solver does, with options from a dict (names as in
/// the registry: "steps", "feed_per_tooth_mm", ...).
struct Built {
  const chatter::SolverDescriptor* descriptor = nullptr;
  std::unique_ptr<chatter::LobeSolver> solver;
  std::vector<std::string> notes;
  chatter::SolverValues values;  ///< the method's options it was built with (checked)
  chatter::SolverRecipe recipe;  ///< method and values: the same solver on another structure or process
};

/// The method's options from the dict, checked, with the CLI's defaults.
chatter::SolverValues solver_values(const chatter::Config& cfg, const chatter::SolverDescriptor& descriptor,
                                    const std::string& method, const std::optional<py::dict>& options);
/// The solver for (method, depth searched, options), from the job's cache.
/// `method` may be "auto" (chatter::resolve_lobe_method, the CLI's rule).
std::shared_ptr<const Built> build_solver(const Job& job, const std::string& method, double depth_max_m,
                                          const std::optional<py::dict>& options);
/// `threads` checked as the CLI's --threads (0 = every core).
unsigned thread_count(int t);
/// Evenly spaced speeds as the CLI's resolve_sweep: arguments, then the
/// config's [sweep].
std::vector<double> even_speeds(const chatter::Config& cfg, std::optional<double> rpm_min,
                                std::optional<double> rpm_max, std::optional<int> rpm_points);

/// A NumPy copy of `v`.
py::array_t<double> array_of(const std::vector<double>& v);

/// A library record (chatter/records.hpp) as Python objects: objects ->
/// dict, arrays -> list, numbers -> int/float, null -> None. The one place a
/// record is handed to Python (no second hand-built copy of a CLI record).
py::object to_python(const nlohmann::json& j);
/// A table result (chatter/records/columns.hpp) as one dict: its fields
/// (to_python), then every column as a NumPy array (numbers float64,
/// integers int, booleans bool, text str, complex complex128; a grid column
/// shaped rows × cols), then each group as a dict of such arrays.
py::dict to_python(const chatter::ColumnRecord& r);
/// The same split for the Result classes that keep fields aside (Lobes,
/// Surface: dict = the columns, info = the fields): (columns, fields).
py::tuple to_python_table(const chatter::ColumnRecord& r);

}  // namespace chatter_py
