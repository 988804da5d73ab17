// Numeric CSV tables: time series written by apps (stress, porosity, energy) and read back by
// tests and calibration. Only plain numbers with a header line: no quoting, no text cells, so
// any spreadsheet, numpy.loadtxt(..., delimiter=",", skiprows=1) or pandas can read them.
//
// Values are printed with 17 significant digits (max_digits10) so that a double survives the
// write/read round trip bit for bit; regression checks can then compare exactly. NaN and inf are
// refused on both sides: in a log they mean the run already went wrong, and they would make the
// file unreadable to read_csv.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace dem::io {

/// An in-memory table that is rewritten whole on every save, so the file on disk is always a
/// complete table even if the run is killed mid-write (see atomic_file.hpp).
class CsvTable {
 public:
  /// Column names: at least one; each non-empty, unique, without commas or line breaks, without
  /// leading/trailing spaces and not starting with '#'. Otherwise dem::InputError.
  explicit CsvTable(std::vector<std::string> columns);

  /// Appends one row. Throws dem::InputError if its size differs from the column count or a
  /// value is NaN/inf (the message names the column).
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
/// not a number, or a NaN/inf cell.
CsvData read_csv(const std::filesystem::path& path);

}  // namespace dem::io
