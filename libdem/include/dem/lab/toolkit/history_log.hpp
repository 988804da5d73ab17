// A protocol's history table (history.csv) as a part: the pieces of a protocol register their
// columns by name, each with the function that measures it, and record() writes one row of all of
// them, in the order they were registered, then saves the file (atomically, io/csv.hpp). A column
// is named once, where it is measured; nothing else lists the columns or their order.
//
//   HistoryLog log(out / "history.csv");
//   log.add("time", [&] { return world.time(); });
//   log.add("vertical_stress", [&] { return world.wall(cell.top).normal_stress(); });
//   add_plate_columns(log, world, cell);   // a part registers its own columns
//   ...
//   log.record();                          // between chunks of steps
//
// Values may be missing (NaN, written "nan"): a measure not defined at that row.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <dem/io/csv.hpp>

namespace dem::lab {

class HistoryLog {
 public:
  /// Appends the values of a group of columns at one row, one per name, in the names' order.
  using Values = std::function<void(std::vector<double>& row)>;

  /// `file` is written by every record(); nothing is written before the first.
  explicit HistoryLog(std::filesystem::path file);

  /// One column. Names are unique, without commas (io::CsvTable's rules); InputError otherwise, or
  /// once a row has been recorded (the columns of a table do not change).
  void add(std::string name, std::function<double()> value);
  /// Several columns that one measurement gives (a profile's bins): `values` appends exactly
  /// names.size() values (record() names the group's first column otherwise).
  void add(std::vector<std::string> names, Values values);
  /// Runs before the columns of every row: a measurement that several columns read, taken once.
  void before_row(std::function<void()> prepare);

  /// Measures every column now, appends the row and saves the file.
  void record();
  /// Keeps the first `rows` rows of a history written earlier (a run resumed from a restart file
  /// written when the history had that many rows), by column name: a column the file lacks is NaN
  /// (a history written before the column existed). Nothing is written until the next record().
  void resume(const std::filesystem::path& written, std::size_t rows);

  const std::vector<std::string>& columns() const { return columns_; }
  /// The rows recorded (and resumed) so far, as written; InputError before a column is added.
  const io::CsvTable& table() const;
  std::size_t rows() const { return table_ ? table_->rows().size() : 0; }
  /// The named column of the last row; `fallback` before the first row.
  double last(const std::string& column, double fallback = 0.0) const;

 private:
  struct Group {
    std::size_t count;
    Values values;
  };
  void add_names(const std::vector<std::string>& names);

  std::filesystem::path file_;
  std::vector<std::string> columns_;
  std::vector<Group> groups_;
  std::vector<std::function<void()>> prepare_;
  std::optional<io::CsvTable> table_;  // from the first column on
};

}  // namespace dem::lab
