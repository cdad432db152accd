// Measured frequency-response functions (FRFs): readers and writers for the
// file formats tap-test software produces. Reference: docs/frf.md.
//
// A table holds one direction term of a receptance (xx, yy or a cross term):
// frequency lines in Hz (as measured) and complex values in m/N. Readers
// convert what the file holds (mobility, accelerance, µm/N, ...) to that.
//
// Formats:
//  - CSV: `frequency_hz, real, imag` per line; comma, semicolon, tab or blank
//    separated; one optional header line; `#`, `%`, `!` and `//` comments.
//  - tab `.frf`: tab (or blank) separated `frequency_hz real imag`; any number
//    of header / comment lines before the data.
//  - Universal File Format dataset 58 (ASCII) and 58b (binary): every FRF
//    record (function type 4), real or complex, single or double, even or
//    uneven abscissa.
//
// Every bad input throws chatter::InputError whose message names the file,
// the UFF record (1-based, counting every dataset in the file) and the line
// (1-based), and the rule:
//   <file>: line 42: decreasing frequency 120 Hz after 130 Hz (frequencies must increase strictly)
//   <file>: record 2, line 31: truncated: expected 512 values, got 300
// Validation common to every reader: at least 2 lines, frequencies finite,
// >= 0 and strictly increasing, values finite.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "chatter/frf_data.hpp"  // FrfTable, validate()
#include "chatter/structural_model.hpp"

namespace chatter {

/// What an FRF file's values are per unit force.
enum class FrfQuantity {
  kReceptance,   ///< displacement / force, m/N (compliance).
  kMobility,     ///< velocity / force, (m/s)/N.
  kAccelerance,  ///< acceleration / force, (m/s²)/N (inertance).
};

/// "receptance", "mobility", "accelerance".
const char* to_string(FrfQuantity q);
/// Parses "receptance" / "compliance", "mobility", "accelerance" / "inertance"
/// (case-insensitive); nullopt for anything else.
std::optional<FrfQuantity> parse_frf_quantity(const std::string& name);

/// Converts a table of `q` to receptance (m/N): mobility / (jω),
/// accelerance / (−ω²), ω = 2π f. Receptance is returned unchanged.
/// @throws InputError naming `t.source` if a mobility or accelerance table has
///         a 0 Hz line (no displacement follows from it: division by zero).
FrfTable to_receptance(FrfTable t, FrfQuantity q);

/// How to read a file's values.
struct FrfReadOptions {
  /// What the values are. CSV / tab: default receptance. UFF: nullopt means
  /// "as the record says" (record 9 ordinate type: 8 displacement,
  /// 11 velocity, 12 acceleration; 0 = unknown is taken as receptance); a
  /// value here overrides the record.
  std::optional<FrfQuantity> quantity;
  /// Factor that turns the file's values into SI (m/N, (m/s)/N, (m/s²)/N):
  /// 1e-6 for µm/N, 1e-3 for mm/N or for (mm/s²)/N. For UFF it multiplies the
  /// factor taken from a units dataset 164 if the file has one.
  double scale = 1.0;
  /// Drop a 0 Hz line instead of refusing it when converting mobility or
  /// accelerance (many analysers start at 0 Hz).
  bool drop_zero_hz = false;
};

/// Reads a CSV table `frequency_hz, real, imag` (exactly three columns).
/// Separators: comma, semicolon (then a comma inside a number is a decimal
/// comma: `650,5;1,2e-7;-3e-8`), tab or blanks. One header line (the first
/// non-comment line, if it is not numeric) is skipped; comment lines start
/// with `#`, `%`, `!` or `//`; blank lines and CRLF endings are fine.
/// @returns the receptance, m/N; `source` = the path.
/// @throws InputError (file, line, column and rule) on anything else.
FrfTable read_frf_csv(const std::filesystem::path& file, const FrfReadOptions& options = {});
FrfTable read_frf_csv(const std::filesystem::path& file, FrfQuantity quantity, double scale = 1.0);

/// Reads the tab-separated `.frf` layout (frequency Hz, real, imaginary):
/// every line before the first numeric line is a header and skipped, as are
/// comment lines anywhere; data lines have three numeric fields separated by
/// tabs (or blanks).
/// @throws InputError as read_frf_csv.
FrfTable read_frf_tab(const std::filesystem::path& file, const FrfReadOptions& options = {});
FrfTable read_frf_tab(const std::filesystem::path& file, FrfQuantity quantity, double scale = 1.0);

/// One FRF record of a Universal File, with what identifies it.
struct UffFrfRecord {
  FrfTable table;             ///< converted to receptance, m/N.
  int record = 0;             ///< 1-based index of the dataset in the file.
  int line = 0;               ///< line where the dataset starts (its `-1`).
  bool binary = false;        ///< 58b.
  int ordinate_data_type = 0; ///< 2 real single, 4 real double, 5 complex single, 6 complex double.
  bool even_abscissa = false;
  FrfQuantity quantity = FrfQuantity::kReceptance;  ///< what the file held before conversion.
  int response_node = 0, response_direction = 0;    ///< record 6 (direction: 1 +X, 2 +Y, 3 +Z, -1 −X, ...).
  int reference_node = 0, reference_direction = 0;
  std::string id1;            ///< record 1 (free text, trimmed).
};

/// Reads every FRF record (dataset 58 / 58b with function type 4) of a
/// Universal File. Other datasets (151, 164, 55, 58 with another function
/// type) are skipped; a units dataset 164 before a record scales it to SI.
/// Tolerates a closing `-1` at any indentation, fields running together in
/// the fixed-width columns (E13.5 single, E20.12 double), Fortran `D`
/// exponents, CRLF endings, blank lines between datasets and a missing final
/// `-1`.
/// @throws InputError naming file, record, line and rule when a record cannot
///         be read, or when no FRF record remains (listing what was skipped).
std::vector<UffFrfRecord> read_uff58_records(const std::filesystem::path& file,
                                             const FrfReadOptions& options = {});
/// The tables of read_uff58_records, in file order.
std::vector<FrfTable> read_uff58(const std::filesystem::path& file, const FrfReadOptions& options = {});

/// The same readers on text / bytes already in memory (tests, fuzzing,
/// files inside archives); `origin` names the source in messages and in
/// `FrfTable::source`.
FrfTable parse_frf_csv(std::string_view text, const std::string& origin, const FrfReadOptions& options = {});
FrfTable parse_frf_tab(std::string_view text, const std::string& origin, const FrfReadOptions& options = {});
std::vector<UffFrfRecord> parse_uff58_records(std::string_view bytes, const std::string& origin,
                                              const FrfReadOptions& options = {});

// ------------------------------------------------------------------ writers
// Writers throw std::invalid_argument for a table that breaks validate() and
// InputError when the file cannot be written.

/// Writes `frequency_hz,real,imag` with 17 significant digits (reads back
/// bit for bit); `header` = true writes a header line first.
void write_frf_csv(const std::filesystem::path& file, const FrfTable& t, bool header = true);
/// Writes the tab `.frf` layout, one comment line and 17 significant digits.
void write_frf_tab(const std::filesystem::path& file, const FrfTable& t);

struct UffWriteOptions {
  bool binary = false;            ///< 58b (little-endian IEEE 754) instead of ASCII 58.
  bool double_precision = true;   ///< ordinate E20.12 / 8 bytes, else E13.5 / 4 bytes.
  bool complex_data = true;       ///< false: real part only (ordinate type 2 / 4).
  /// Even abscissa: minimum and increment in record 7 (E13.5 in ASCII: hold
  /// 6 significant digits). The table must be evenly spaced to 1e-9.
  bool even_abscissa = true;
  FrfQuantity quantity = FrfQuantity::kReceptance;  ///< record 9 ordinate type written (values as given).
  int response_node = 1, response_direction = 1;
  int reference_node = 1, reference_direction = 1;
  std::string id1 = "chatter FRF";
};
/// Writes one dataset 58 / 58b per table. Uneven abscissa values are written
/// E13.5 in ASCII (as dataset 58 prescribes: 6 significant digits) and in
/// the ordinate precision in binary.
void write_uff58(const std::filesystem::path& file, const std::vector<FrfTable>& tables,
                 const UffWriteOptions& options = {});

}  // namespace chatter
