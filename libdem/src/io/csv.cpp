// CSV writing and reading. Parsing uses std::from_chars: it ignores the global locale (a German
// locale would otherwise read "0,5"), and reports exactly how much of a cell it consumed.
#include "dem/io/csv.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <locale>
#include <optional>
#include <string_view>
#include <system_error>

#include "dem/base/input_file.hpp"
#include "dem/core/errors.hpp"
#include "dem/io/atomic_file.hpp"

namespace dem::io {
namespace {

std::string_view trim(std::string_view text) {
  const auto first = text.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  const auto last = text.find_last_not_of(" \t\r");
  return text.substr(first, last - first + 1);
}

std::vector<std::string_view> split_commas(std::string_view line) {
  std::vector<std::string_view> cells;
  std::size_t start = 0;
  while (true) {
    const auto comma = line.find(',', start);
    cells.push_back(trim(line.substr(start, comma - start)));
    if (comma == std::string_view::npos) return cells;
    start = comma + 1;
  }
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& name : names) out += (out.empty() ? "" : ", ") + name;
  return out;
}

std::size_t find_column(const std::vector<std::string>& columns, const std::string& name) {
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i] == name) return i;
  throw InputError("CSV column '" + name + "' does not exist; columns are: " + joined(columns));
}

// Empty string if the name is usable, else what is wrong with it.
std::string column_name_problem(const std::string& name) {
  if (name.empty()) return "is empty";
  if (name.find_first_of(",\r\n") != std::string::npos) return "contains a comma or line break";
  if (trim(name).size() != name.size()) return "has leading or trailing spaces";
  if (name.front() == '#') return "starts with '#' (would read as a comment line)";
  return {};
}

void check_columns(const std::vector<std::string>& columns, const std::string& where) {
  if (columns.empty()) throw InputError(where + "CSV needs at least one column");
  for (std::size_t i = 0; i < columns.size(); ++i) {
    const std::string problem = column_name_problem(columns[i]);
    if (!problem.empty())
      throw InputError(where + "CSV column " + std::to_string(i + 1) + " name '" + columns[i] +
                       "' " + problem);
    for (std::size_t j = 0; j < i; ++j)
      if (columns[j] == columns[i])
        throw InputError(where + "CSV column name '" + columns[i] + "' appears twice (columns " +
                         std::to_string(j + 1) + " and " + std::to_string(i + 1) + ")");
  }
}

// The parsed value, or nullopt with `problem` filled in.
std::optional<double> parse_cell(std::string_view cell, std::string& problem, Missing missing) {
  if (!cell.empty() && cell.front() == '+' && cell.substr(1, 1) != "-") cell.remove_prefix(1);
  double value = 0.0;
  const auto [end, error] = std::from_chars(cell.data(), cell.data() + cell.size(), value);
  if (error == std::errc::result_out_of_range) {
    problem = "is out of the range of a double";
  } else if (error != std::errc() || end != cell.data() + cell.size()) {
    problem = "is not a number";
  } else if (std::isnan(value) && missing == Missing::Allowed) {
    return std::numeric_limits<double>::quiet_NaN();
  } else if (!std::isfinite(value)) {
    problem = missing == Missing::Allowed ? "is infinite; only finite numbers or nan are allowed"
                                          : "is NaN or infinite; only finite numbers are allowed";
  } else {
    return value;
  }
  return std::nullopt;
}

}  // namespace

CsvTable::CsvTable(std::vector<std::string> columns, Missing missing) : columns_(std::move(columns)), missing_(missing) {
  check_columns(columns_, "");
}

void CsvTable::add_row(const std::vector<double>& row) {
  if (row.size() != columns_.size())
    throw InputError("CSV row has " + std::to_string(row.size()) + " values: must have " +
                     std::to_string(columns_.size()) + " (columns " + joined(columns_) + ")");
  for (std::size_t i = 0; i < row.size(); ++i)
    require(std::isfinite(row[i]) || (std::isnan(row[i]) && missing_ == Missing::Allowed),
            "CSV value in column '" + columns_[i] + "'", row[i],
            missing_ == Missing::Allowed ? "a finite number or NaN (missing)" : "a finite number");
  rows_.push_back(row);
}

void CsvTable::save(const std::filesystem::path& path) const {
  write_atomically(path, [this](std::ostream& out) {
    out.imbue(std::locale::classic());
    out.precision(std::numeric_limits<double>::max_digits10);
    for (std::size_t i = 0; i < columns_.size(); ++i) out << (i ? "," : "") << columns_[i];
    out << '\n';
    for (const auto& row : rows_) {
      for (std::size_t i = 0; i < row.size(); ++i) {
        out << (i ? "," : "");
        if (std::isnan(row[i]))
          out << "nan";
        else
          out << row[i];
      }
      out << '\n';
    }
  });
}

std::size_t CsvTable::column_index(const std::string& name) const {
  return find_column(columns_, name);
}

std::size_t CsvData::column(const std::string& name) const { return find_column(columns, name); }

CsvData read_csv(const std::filesystem::path& path, Missing missing) {
  require_input_file(path, "CSV file", "a CSV file", max_text_input_bytes);
  std::ifstream in(path);
  if (!in) {
    std::error_code ec;
    const bool exists = std::filesystem::exists(path, ec);
    throw InputError("CSV file " + path.string() +
                     (exists ? ": cannot be opened for reading" : ": does not exist"));
  }
  CsvData data;
  bool have_header = false;
  std::string line;
  for (std::size_t line_number = 1; std::getline(in, line); ++line_number) {
    const std::string_view content = trim(line);
    if (content.empty() || content.front() == '#') continue;
    const std::string where = path.string() + ":" + std::to_string(line_number) + ": ";
    const auto cells = split_commas(content);
    if (!have_header) {
      for (const auto cell : cells) data.columns.emplace_back(cell);
      check_columns(data.columns, where);
      have_header = true;
      continue;
    }
    if (cells.size() != data.columns.size())
      throw InputError(where + "row has " + std::to_string(cells.size()) + " cells: must have " +
                       std::to_string(data.columns.size()) + " (columns " +
                       joined(data.columns) + ")");
    std::vector<double> row(cells.size());
    for (std::size_t i = 0; i < cells.size(); ++i) {
      std::string problem;
      const auto value = parse_cell(cells[i], problem, missing);
      if (!value)
        throw InputError(where + "cell '" + std::string(cells[i]) + "' in column '" +
                         data.columns[i] + "' " + problem);
      row[i] = *value;
    }
    data.rows.push_back(std::move(row));
  }
  if (in.bad()) throw InputError("CSV file " + path.string() + ": read error");
  if (!have_header)
    throw InputError("CSV file " + path.string() + ": is empty (no header line found)");
  return data;
}

}  // namespace dem::io
