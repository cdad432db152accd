// A measured frequency-response function (FRF) as plain data: the input of
// the modal fit (modal_fit.hpp) and of measured-FRF solvers, whatever file it
// came from. The file readers and writers are in the io layer
// (chatter/io/frf.hpp); this header depends on nothing but the model.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "chatter/structural_model.hpp"

namespace chatter {

/// One measured direction term of a receptance.
struct FrfTable {
  std::vector<double> frequency_hz;  ///< frequency lines, Hz, finite, >= 0, strictly increasing.
  std::vector<Complex> value;        ///< receptance at each line, m/N (same size as frequency_hz).
  std::string source;                ///< where it came from: "<file>" or "<file> (record <n>)".

  std::size_t size() const { return frequency_hz.size(); }
};

/// Checks the rules every reader applies (>= 2 lines, sizes equal,
/// frequencies finite, >= 0, strictly increasing, values finite).
/// Cost O(lines).
/// @throws InputError naming `t.source` and the offending line index.
void validate(const FrfTable& t);

/// The same rules with the caller's names for the places: `whole` for the
/// table (e.g. the file), `where(i)` for line index i (e.g. "<file>: line 42").
/// @throws InputError "<where(i)>: <rule>" or "<whole>: <rule>".
void validate(const FrfTable& t, const std::string& whole, const std::function<std::string(std::size_t)>& where);

}  // namespace chatter
