#!/usr/bin/env bash
# The include rules of the layers (docs/architecture.md), checked on the
# sources: prints every #include that breaks one and fails if any does.
#   core (src/model, src/solvers, src/grinding, src/shop, include/chatter/*.hpp but operations.hpp,
#        optimization.hpp, pitch_design.hpp and records.hpp):
#        Eigen, SUNDIALS, the standard library, header-only Boost.Math (no
#        link dependency) and other core headers only.
#   io   (src/config, src/formats, src/plots, include/chatter/io): core data
#        headers and the solver registry (chatter/solvers.hpp: descriptors,
#        plot styles), toml++, nlohmann; no solver class header, no ops, no
#        Boost. Inside it, three rooms of one concern each:
#          config  (src/config): the TOML config reader; no plot;
#          formats (src/formats): file formats (FRF, tables, shop data,
#                  the NC program's canon log); no plot, no config internals;
#          plots   (src/plots): gnuplot scripts; no toml++, no config or
#                  format internals.
#   ops  (src/ops, include/chatter/operations.hpp, optimization.hpp, pitch_design.hpp): core only.
#   records (src/records, include/chatter/records.hpp, include/chatter/records/):
#        no Boost, toml++ or CLI header.
#   gnuplot-iostream (and Boost.Iostreams) only in src/cli/live_plot.cpp
#        (the `chatter` executable's live plots; nothing else links them).
#   MPI  (mpi.h) only in src/mpi (chatter-mpi).
# Usage: check_layers.sh SOURCE_DIR
set -uo pipefail
src=$1
cd "$src" || exit 2
bad=0
# check <what> <extended regex of forbidden #include targets> <files...>
check() {
  local what=$1 pattern=$2
  shift 2
  local hits
  hits=$(grep -HnE "^[[:space:]]*#[[:space:]]*include[[:space:]]*[<\"]($pattern)" "$@" 2>/dev/null)
  if [[ -n $hits ]]; then
    echo "$what:"
    echo "$hits"
    bad=1
  fi
}
core_headers=$(ls include/chatter/*.hpp | grep -v -E '/(operations|optimization|pitch_design|records)\.hpp$')
check "core includes io, ops, a file-format library or Boost (but header-only Boost.Math)" \
  'chatter/io/|chatter/operations\.hpp|chatter/optimization\.hpp|chatter/pitch_design\.hpp|chatter/records|chatter/chatter\.h|toml\+\+|nlohmann|boost/[^m]|boost/m[^a]|gnuplot' \
  $(find src/model src/solvers src/grinding src/shop src/toolpath -type f) $core_headers
check "io includes a solver class header, ops, records or Boost" \
  'chatter/(semi_discretization|time_domain|transfer_function|grinding_dynamics)\.hpp|chatter/operations\.hpp|chatter/pitch_design\.hpp|chatter/records\.hpp|boost|(\.\./)+(solvers|ops|cli|records)/' \
  src/config/* src/formats/* src/plots/* include/chatter/io/*
check "config (src/config) includes a plot" 'chatter/io/plot|plot_kit\.hpp|plot_files\.hpp|(\.\./)+plots/' src/config/*
check "formats (src/formats) includes a plot or the config reader's internals" \
  'chatter/io/plot|plot_kit\.hpp|plot_files\.hpp|config_read\.hpp|config_sections\.hpp|(\.\./)+(plots|config)/' src/formats/*
check "plots (src/plots) includes toml++ or the config reader's or a format's internals" \
  'toml\+\+|config_read\.hpp|config_sections\.hpp|text\.hpp|(\.\./)+(config|formats)/' src/plots/*
check "ops includes io, records, a file-format library or Boost" \
  'chatter/io/|chatter/records\.hpp|toml\+\+|nlohmann|boost' \
  src/ops/* include/chatter/operations.hpp include/chatter/optimization.hpp include/chatter/pitch_design.hpp
check "records includes Boost, toml++ or the CLI" 'boost|toml\+\+|gnuplot-iostream|(\.\./)+cli/' src/records/* include/chatter/records.hpp \
  include/chatter/records/*
check "gnuplot-iostream (and the Boost.Iostreams it pulls in) outside src/cli/live_plot.cpp" \
  'gnuplot-iostream|boost/iostreams' $(ls src/*/*.cpp src/*/*.hpp include/chatter/*.hpp include/chatter/*/*.hpp python/*.cpp python/*.hpp | grep -v 'src/cli/live_plot\.cpp$')
check "Boost outside the CLI" 'boost' src/capi/* include/chatter/chatter.h
check "MPI outside src/mpi (the library and the chatter CLI link no MPI: docs/scaling.md)" 'mpi\.h|openmpi' \
  src/model/* src/solvers/* src/grinding/* src/config/* src/formats/* src/plots/* src/ops/* src/shop/* src/records/* src/capi/* src/cli/* include/chatter/*.hpp include/chatter/io/* \
  include/chatter/chatter.h
if [[ $bad -ne 0 ]]; then
  echo "layer rules broken (docs/architecture.md)"
  exit 1
fi
echo "layer include rules: ok"
