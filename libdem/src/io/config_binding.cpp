#include <dem/io/config_binding.hpp>

#include <cstdio>
#include <string>

namespace dem::io {

std::string real_text(double value) {
  char text[32];
  for (int digits = 6; digits <= 17; ++digits) {  // the shortest that reads back exactly
    std::snprintf(text, sizeof text, "%.*g", digits, value);
    if (std::stod(text) == value) break;
  }
  return text;
}

std::string real_list_text(const std::vector<double>& values) {
  std::string out;
  for (double v : values) out += (out.empty() ? "" : ",") + real_text(v);
  return out;
}

}  // namespace dem::io
