// Fuzz target: the numeric CSV reader, io::read_csv; the input is the file's bytes. Besides
// "InputError or nothing", what it accepts must be a rectangular table of finite numbers that
// CsvTable writes back and read_csv reads again to the same names and bit-identical values.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>
#include <vector>

#include <dem/io/csv.hpp>

#include "fuzz_support.hpp"

using namespace dem;

namespace {

bool same_bits(const std::vector<std::vector<double>>& a, const std::vector<std::vector<double>>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t r = 0; r < a.size(); ++r)
    if (a[r].size() != b[r].size() || std::memcmp(a[r].data(), b[r].data(), a[r].size() * sizeof(double)) != 0)
      return false;
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = fuzz::scratch("input.csv");
  fuzz::write_bytes(file, std::string_view(reinterpret_cast<const char*>(data), size));
  io::CsvData table;
  if (fuzz::refuses_cleanly([&] { table = io::read_csv(file); }, file.string())) return 0;

  fuzz::check(!table.columns.empty(), "read_csv accepted a table without columns");
  for (const auto& row : table.rows) {
    fuzz::check(row.size() == table.columns.size(), "read_csv returned a row of the wrong length");
    for (const double v : row) fuzz::check(std::isfinite(v), "read_csv returned a NaN or infinite value");
  }
  const auto copy = fuzz::scratch("copy.csv");
  if (fuzz::refuses_cleanly([&] {
        io::CsvTable out(table.columns);
        for (const auto& row : table.rows) out.add_row(row);
        out.save(copy);
      }))
    fuzz::fail("CsvTable refuses a table that read_csv accepted");
  io::CsvData again;
  if (fuzz::refuses_cleanly([&] { again = io::read_csv(copy); }))
    fuzz::fail("read_csv refuses the file CsvTable wrote");
  fuzz::check(again.columns == table.columns, "column names changed in a write/read round trip");
  fuzz::check(same_bits(again.rows, table.rows), "values changed in a write/read round trip");
  return 0;
}
