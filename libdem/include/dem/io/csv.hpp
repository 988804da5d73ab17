// Numeric CSV tables: time series written by apps (stress, porosity, energy) and read back by
// tests and calibration. Only plain numbers with a header line: no quoting, no text cells, so
// any spreadsheet, numpy.loadtxt(..., delimiter=",", skiprows=1) or pandas can read them.
//
// Values are printed with 17 significant digits (max_digits10) so that a double survives the
// write/read round trip bit for bit; regression checks can then compare exactly. NaN and inf are
// refused on both sides by default: in a log they mean the run already went wrong. A table may
// instead declare that a value can be missing (a measure not defined at that row, such as an
// increment before the first interval): NaN is then written as "nan", which NumPy, pandas and
// read_csv(path, Missing::Allowed) read back as NaN. Infinities are refused always.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace dem::io {

/// Whether NaN ("nan") stands for a missing value in a table.
enum class Missing { Refused, Allowed };

/// An in-memory table that is rewritten whole on every save, so the file on disk is always a
/// complete table even if the run is killed mid-write (see atomic_file.hpp).
class CsvTable {
 public:
  /// Column names: at least one; each non-empty, unique, without commas or line breaks, without
  /// leading/trailing spaces and not starting with '#'. Otherwise dem::InputError.
  explicit CsvTable(std::vector<std::string> columns, Missing missing = Missing::Refused);

  /// Appends one row. Throws dem::InputError if its size differs from the column count or a
  /// value is infinite, or NaN in a table that refuses missing values (the message names the column).
  void add_row(const std::vector<double>& row);

  /// Writes the header line and all rows to `path`, replacing it atomically.
  void save(const std::filesystem::path& path) const;

  const std::vector<std::vector<double>>& rows() const { return rows_; }
  const std::vector<std::string>& columns() const { return columns_; }

  /// Index of the named column; dem::InputError listing the columns if there is none.
  std::size_t column_index(const std::string& name) const;

 private:
  std::vector<std::string> columns_;
  std::vector<std::vector<double>> rows_;
  Missing missing_ = Missing::Refused;
};

/// A numeric CSV file as read by read_csv.
struct CsvData {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;  // every row has columns.size() values

  /// Index of the named column; dem::InputError listing the columns if there is none.
  std::size_t column(const std::string& name) const;
};

/// Reads a CSV of finite numbers with one header line. Blank lines and lines starting with '#'
/// are skipped; spaces around cells are trimmed; "\r\n" line ends are accepted. Throws
/// dem::InputError naming the file and line for: a missing or unreadable file, no header, an
/// invalid header (empty or duplicate name), a row with the wrong number of cells, a cell that is
/// not a number, an infinite cell, or a NaN cell unless `missing` is Allowed.
CsvData read_csv(const std::filesystem::path& path, Missing missing = Missing::Refused);

}  // namespace dem::io
