#include <dem/lab/toolkit/history_log.hpp>

#include <algorithm>
#include <limits>

#include <dem/core/errors.hpp>

namespace dem::lab {

HistoryLog::HistoryLog(std::filesystem::path file) : file_(std::move(file)) {}

void HistoryLog::add_names(const std::vector<std::string>& names) {
  require(rows() == 0, "history column '" + (names.empty() ? std::string() : names.front()) + "'",
          "added after " + std::to_string(rows()) + " row(s)", "columns added before the first row");
  std::vector<std::string> columns = columns_;
  columns.insert(columns.end(), names.begin(), names.end());
  table_.emplace(columns, io::Missing::Allowed);  // checks the names: unique, no commas
  columns_ = std::move(columns);
}

void HistoryLog::add(std::string name, std::function<double()> value) {
  add_names({name});
  groups_.push_back({1, [value = std::move(value)](std::vector<double>& row) { row.push_back(value()); }});
}

void HistoryLog::add(std::vector<std::string> names, Values values) {
  require(!names.empty(), "history column group", "no names", "at least one column");
  add_names(names);
  groups_.push_back({names.size(), std::move(values)});
}

void HistoryLog::before_row(std::function<void()> prepare) { prepare_.push_back(std::move(prepare)); }

const io::CsvTable& HistoryLog::table() const {
  require(table_.has_value(), "history table", "no columns", "columns added before it is read");
  return *table_;
}

void HistoryLog::record() {
  table();  // InputError without columns
  for (const auto& prepare : prepare_) prepare();
  std::vector<double> row;
  row.reserve(columns_.size());
  for (const Group& group : groups_) {
    const std::size_t before = row.size();
    group.values(row);
    require(row.size() - before == group.count, "history columns from '" + columns_[before] + "'",
            std::to_string(row.size() - before) + " values", std::to_string(group.count) + ", one per column");
  }
  table_->add_row(row);
  table_->save(file_);
}

void HistoryLog::resume(const std::filesystem::path& written, std::size_t rows) {
  table();  // InputError without columns
  table_.emplace(columns_, io::Missing::Allowed);
  if (rows == 0) return;
  const io::CsvData old = io::read_csv(written, io::Missing::Allowed);
  require(old.rows.size() >= rows, written.string() + " rows", old.rows.size(),
          ">= " + std::to_string(rows) + " (as in the restart file)");
  std::vector<std::ptrdiff_t> source;  // column of the file for each of ours, -1 if it has none
  for (const std::string& name : columns_) {
    const auto it = std::find(old.columns.begin(), old.columns.end(), name);
    source.push_back(it == old.columns.end() ? -1 : it - old.columns.begin());
  }
  for (std::size_t r = 0; r < rows; ++r) {
    std::vector<double> row;
    for (std::ptrdiff_t c : source)
      row.push_back(c < 0 ? std::numeric_limits<double>::quiet_NaN() : old.rows[r][static_cast<std::size_t>(c)]);
    table_->add_row(row);
  }
}

double HistoryLog::last(const std::string& column, double fallback) const {
  if (rows() == 0) return fallback;
  return table_->rows().back()[table_->column_index(column)];
}

}  // namespace dem::lab
