// JSON writing and a recursive-descent parser (RFC 8259). Numbers go through std::to_chars and
// std::from_chars: both ignore the global locale (a German locale would otherwise write "0,5").
#include "dem/io/json.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <ostream>
#include <system_error>

#include "dem/core/errors.hpp"
#include "dem/io/atomic_file.hpp"

namespace dem::io {
namespace {

const char* type_name(Json::Type type) {
  switch (type) {
    case Json::Type::Null:
      return "null";
    case Json::Type::Bool:
      return "a boolean";
    case Json::Type::Number:
      return "a number";
    case Json::Type::String:
      return "a string";
    case Json::Type::Array:
      return "an array";
    case Json::Type::Object:
      return "an object";
  }
  return "?";
}

[[noreturn]] void wrong_type(Json::Type have, const std::string& wanted) {
  throw InputError(std::string("JSON value is ") + type_name(have) + ": must be " + wanted);
}

void append_number(std::string& out, double value) {
  if (!std::isfinite(value)) {
    out += "null";
    return;
  }
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::general, 17);
  out.append(buffer, result.ptr);
}

void append_string(std::string& out, const std::string& text) {
  static const char hex[] = "0123456789abcdef";
  out += '"';
  for (const char c : text) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\b':
        out += "\\b";
        break;
      case '\f':
        out += "\\f";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\r':
        out += "\\r";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          out += "\\u00";
          out += hex[static_cast<unsigned char>(c) >> 4];
          out += hex[static_cast<unsigned char>(c) & 0xf];
        } else {
          out += c;
        }
    }
  }
  out += '"';
}

void append_newline(std::string& out, int indent, int depth) {
  if (indent == 0) return;
  out += '\n';
  out.append(static_cast<std::size_t>(indent) * static_cast<std::size_t>(depth), ' ');
}

void append_value(std::string& out, const Json& value, int indent, int depth) {
  switch (value.type()) {
    case Json::Type::Null:
      out += "null";
      return;
    case Json::Type::Bool:
      out += value.as_bool() ? "true" : "false";
      return;
    case Json::Type::Number:
      append_number(out, value.as_number());
      return;
    case Json::Type::String:
      append_string(out, value.as_string());
      return;
    case Json::Type::Array:
    case Json::Type::Object:
      break;
  }
  const bool object = value.type() == Json::Type::Object;
  out += object ? '{' : '[';
  for (std::size_t i = 0; i < value.size(); ++i) {
    if (i > 0) out += ',';
    append_newline(out, indent, depth + 1);
    if (object) {
      append_string(out, value.keys()[i]);
      out += indent > 0 ? ": " : ":";
    }
    append_value(out, value.items()[i], indent, depth + 1);
  }
  if (value.size() > 0) append_newline(out, indent, depth);
  out += object ? '}' : ']';
}

// Recursive descent over the whole text; `pos` is the next unread byte.
class Parser {
 public:
  Parser(const std::string& text, std::string where) : text_(text), where_(std::move(where)) {}

  Json document() {
    skip_space();
    Json value = parse_value(0);
    skip_space();
    if (pos_ != text_.size()) fail("unexpected text after the JSON value");
    return value;
  }

 private:
  static constexpr int max_depth = 512;

  [[noreturn]] void fail(const std::string& problem) const { fail_at(pos_, problem); }

  [[noreturn]] void fail_at(std::size_t at, const std::string& problem) const {
    std::size_t line = 1, column = 1;
    for (std::size_t i = 0; i < at && i < text_.size(); ++i) {
      if (text_[i] == '\n') {
        ++line;
        column = 1;
      } else {
        ++column;
      }
    }
    throw InputError(where_ + "JSON text at line " + std::to_string(line) + ", column " + std::to_string(column) +
                     ": " + problem);
  }

  bool at_end() const { return pos_ >= text_.size(); }
  char peek() const { return at_end() ? '\0' : text_[pos_]; }

  void skip_space() {
    while (!at_end() && (peek() == ' ' || peek() == '\t' || peek() == '\n' || peek() == '\r')) ++pos_;
  }

  void expect(char c, const char* what) {
    if (peek() != c) fail(std::string("expected ") + what);
    ++pos_;
  }

  Json parse_value(int depth) {
    if (at_end()) fail("unexpected end of text, expected a value");
    switch (peek()) {
      case '{':
        return parse_object(depth + 1);
      case '[':
        return parse_array(depth + 1);
      case '"':
        return Json(parse_string());
      case 't':
        literal("true");
        return Json(true);
      case 'f':
        literal("false");
        return Json(false);
      case 'n':
        literal("null");
        return Json();
      default:
        if (peek() == '-' || (peek() >= '0' && peek() <= '9')) return Json(parse_number());
        fail(std::string("unexpected character '") + peek() + "', expected a value");
    }
  }

  void literal(const std::string& word) {
    if (text_.compare(pos_, word.size(), word) != 0) fail("invalid literal, expected '" + word + "'");
    pos_ += word.size();
  }

  void check_depth(int depth) const {
    if (depth > max_depth) fail("nesting deeper than " + std::to_string(max_depth) + " levels");
  }

  Json parse_object(int depth) {
    check_depth(depth);
    ++pos_;  // '{'
    Json object = Json::object();
    skip_space();
    if (peek() == '}') {
      ++pos_;
      return object;
    }
    while (true) {
      skip_space();
      if (peek() != '"') fail("expected a string key in an object");
      const std::size_t key_at = pos_;
      std::string key = parse_string();
      if (object.contains(key)) fail_at(key_at, "duplicate object key \"" + key + "\"");
      skip_space();
      expect(':', "':' after an object key");
      skip_space();
      object[key] = parse_value(depth);
      skip_space();
      if (peek() == '}') {
        ++pos_;
        return object;
      }
      expect(',', "',' or '}' in an object");
    }
  }

  Json parse_array(int depth) {
    check_depth(depth);
    ++pos_;  // '['
    Json array = Json::array();
    skip_space();
    if (peek() == ']') {
      ++pos_;
      return array;
    }
    while (true) {
      skip_space();
      array.push_back(parse_value(depth));
      skip_space();
      if (peek() == ']') {
        ++pos_;
        return array;
      }
      expect(',', "',' or ']' in an array");
    }
  }

  bool is_digit() const { return !at_end() && peek() >= '0' && peek() <= '9'; }

  // RFC 8259 number grammar: -? (0 | [1-9][0-9]*) (. [0-9]+)? ([eE] [+-]? [0-9]+)?
  double parse_number() {
    const std::size_t start = pos_;
    if (peek() == '-') ++pos_;
    if (peek() == '0') {
      ++pos_;
    } else if (is_digit()) {
      while (is_digit()) ++pos_;
    } else {
      fail("a number needs digits after '-'");
    }
    if (peek() == '.') {
      ++pos_;
      if (!is_digit()) fail("a number needs digits after '.'");
      while (is_digit()) ++pos_;
    }
    if (peek() == 'e' || peek() == 'E') {
      ++pos_;
      if (peek() == '+' || peek() == '-') ++pos_;
      if (!is_digit()) fail("a number needs digits in its exponent");
      while (is_digit()) ++pos_;
    }
    double value = 0.0;
    const auto [end, error] = std::from_chars(text_.data() + start, text_.data() + pos_, value);
    if (error == std::errc::result_out_of_range)
      fail_at(start, "number " + text_.substr(start, pos_ - start) + " is outside the range of a double");
    if (error != std::errc() || end != text_.data() + pos_)
      fail_at(start, "invalid number " + text_.substr(start, pos_ - start));
    return value;
  }

  unsigned hex4() {
    if (pos_ + 4 > text_.size()) fail("\\u needs four hexadecimal digits");
    unsigned value = 0;
    for (int k = 0; k < 4; ++k) {
      const char c = text_[pos_++];
      value <<= 4;
      if (c >= '0' && c <= '9')
        value |= static_cast<unsigned>(c - '0');
      else if (c >= 'a' && c <= 'f')
        value |= static_cast<unsigned>(c - 'a' + 10);
      else if (c >= 'A' && c <= 'F')
        value |= static_cast<unsigned>(c - 'A' + 10);
      else
        fail_at(pos_ - 1, "\\u needs four hexadecimal digits");
    }
    return value;
  }

  static void append_utf8(std::string& out, unsigned code) {
    if (code < 0x80) {
      out += static_cast<char>(code);
    } else if (code < 0x800) {
      out += static_cast<char>(0xc0 | (code >> 6));
      out += static_cast<char>(0x80 | (code & 0x3f));
    } else if (code < 0x10000) {
      out += static_cast<char>(0xe0 | (code >> 12));
      out += static_cast<char>(0x80 | ((code >> 6) & 0x3f));
      out += static_cast<char>(0x80 | (code & 0x3f));
    } else {
      out += static_cast<char>(0xf0 | (code >> 18));
      out += static_cast<char>(0x80 | ((code >> 12) & 0x3f));
      out += static_cast<char>(0x80 | ((code >> 6) & 0x3f));
      out += static_cast<char>(0x80 | (code & 0x3f));
    }
  }

  // A \u escape, with the second half of a UTF-16 surrogate pair if the first needs one.
  unsigned unicode_escape() {
    const std::size_t start = pos_ - 2;
    const unsigned code = hex4();
    if (code >= 0xdc00 && code <= 0xdfff) fail_at(start, "lone UTF-16 low surrogate in \\u escape");
    if (code < 0xd800 || code > 0xdbff) return code;
    if (text_.compare(pos_, 2, "\\u") != 0) fail_at(start, "UTF-16 high surrogate without its low half");
    pos_ += 2;
    const unsigned low = hex4();
    if (low < 0xdc00 || low > 0xdfff) fail_at(start, "UTF-16 high surrogate without its low half");
    return 0x10000 + ((code - 0xd800) << 10) + (low - 0xdc00);
  }

  std::string parse_string() {
    const std::size_t start = pos_;
    ++pos_;  // opening quote
    std::string out;
    while (true) {
      if (at_end()) fail_at(start, "string is not closed");
      const char c = text_[pos_++];
      if (c == '"') return out;
      if (static_cast<unsigned char>(c) < 0x20) fail_at(pos_ - 1, "control character in a string (must be escaped)");
      if (c != '\\') {
        out += c;
        continue;
      }
      if (at_end()) fail_at(start, "string is not closed");
      const char e = text_[pos_++];
      switch (e) {
        case '"':
          out += '"';
          break;
        case '\\':
          out += '\\';
          break;
        case '/':
          out += '/';
          break;
        case 'b':
          out += '\b';
          break;
        case 'f':
          out += '\f';
          break;
        case 'n':
          out += '\n';
          break;
        case 'r':
          out += '\r';
          break;
        case 't':
          out += '\t';
          break;
        case 'u':
          append_utf8(out, unicode_escape());
          break;
        default:
          fail_at(pos_ - 2, std::string("invalid escape '\\") + e + "' in a string");
      }
    }
  }

  const std::string& text_;
  std::string where_;
  std::size_t pos_ = 0;
};

}  // namespace

Json Json::array(std::vector<Json> items) {
  Json value;
  value.type_ = Type::Array;
  value.items_ = std::move(items);
  return value;
}

Json Json::object() {
  Json value;
  value.type_ = Type::Object;
  return value;
}

bool Json::as_bool() const {
  if (type_ != Type::Bool) wrong_type(type_, "a boolean");
  return bool_;
}

double Json::as_number() const {
  if (type_ != Type::Number) wrong_type(type_, "a number");
  return number_;
}

const std::string& Json::as_string() const {
  if (type_ != Type::String) wrong_type(type_, "a string");
  return string_;
}

Json& Json::operator[](const std::string& key) {
  if (type_ == Type::Null) type_ = Type::Object;
  if (type_ != Type::Object) wrong_type(type_, "an object to look up key \"" + key + "\"");
  for (std::size_t i = 0; i < keys_.size(); ++i)
    if (keys_[i] == key) return items_[i];
  keys_.push_back(key);
  items_.emplace_back();
  return items_.back();
}

const Json& Json::at(const std::string& key) const {
  if (type_ != Type::Object) wrong_type(type_, "an object to look up key \"" + key + "\"");
  for (std::size_t i = 0; i < keys_.size(); ++i)
    if (keys_[i] == key) return items_[i];
  std::string known;
  for (const auto& k : keys_) known += (known.empty() ? "" : ", ") + k;
  throw InputError("JSON object key \"" + key + "\" does not exist; keys are: " + known);
}

bool Json::contains(const std::string& key) const {
  if (type_ != Type::Object) return false;
  for (const auto& k : keys_)
    if (k == key) return true;
  return false;
}

void Json::push_back(Json value) {
  if (type_ == Type::Null) type_ = Type::Array;
  if (type_ != Type::Array) wrong_type(type_, "an array to append to");
  items_.push_back(std::move(value));
}

const Json& Json::at(std::size_t index) const {
  if (type_ != Type::Array) wrong_type(type_, "an array to take element " + std::to_string(index));
  require(index < items_.size(), "JSON array index", index, "< the array size " + std::to_string(items_.size()));
  return items_[index];
}

std::string Json::dump(int indent) const {
  require(indent >= 0, "JSON indent", indent, ">= 0 (0 writes one line)");
  std::string out;
  append_value(out, *this, indent, 0);
  return out;
}

void Json::save(const std::filesystem::path& path, int indent) const {
  const std::string text = dump(indent);
  write_atomically(path, [&](std::ostream& out) { out << text << '\n'; });
}

Json Json::parse(const std::string& text) { return Parser(text, "").document(); }

Json Json::load(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("JSON file " + path.string() + " cannot be opened");
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) throw InputError("JSON file " + path.string() + " cannot be read");
  return Parser(text, "JSON file " + path.string() + ": ").document();
}

bool operator==(const Json& a, const Json& b) {
  if (a.type_ != b.type_) return false;
  switch (a.type_) {
    case Json::Type::Null:
      return true;
    case Json::Type::Bool:
      return a.bool_ == b.bool_;
    case Json::Type::Number:
      return a.number_ == b.number_;
    case Json::Type::String:
      return a.string_ == b.string_;
    case Json::Type::Array:
    case Json::Type::Object:
      return a.keys_ == b.keys_ && a.items_ == b.items_;
  }
  return false;
}

}  // namespace dem::io
