// A small JSON value for summary files (summary.json of a run: counts, porosity, peak values,
// the resolved configuration), and a parser so that tests and tools can read them back.
//
// Why not Boost.PropertyTree's JSON writer: it stores every value as a string (numbers come back
// quoted), and it cannot write arrays of numbers. Why not a full JSON library: libdem needs only
// to write small documents and read its own output; this file is the whole dependency.
//
// Objects keep their keys in insertion order, so a summary reads in the order the app wrote it
// (lookups are linear, which is fine for documents of tens of keys). Numbers are doubles written
// with 17 significant digits, so every finite double survives dump -> parse bit for bit; integers
// up to 2^53 are exact. JSON has no NaN or infinity: they are written as null (a quantity that
// could not be measured) and therefore read back as null.
#pragma once

#include <concepts>
#include <cstddef>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace dem::io {

class Json {
 public:
  enum class Type { Null, Bool, Number, String, Array, Object };

  /// null
  Json() = default;
  Json(std::nullptr_t) {}
  Json(bool value) : type_(Type::Bool), bool_(value) {}
  Json(double value) : type_(Type::Number), number_(value) {}
  /// Any integer type (counts, indices); stored as a double, exact up to 2^53.
  template <std::integral Integer>
  requires(!std::same_as<Integer, bool>) Json(Integer value)
      : type_(Type::Number), number_(static_cast<double>(value)) {}
  Json(std::string value) : type_(Type::String), string_(std::move(value)) {}
  Json(const char* value) : type_(Type::String), string_(value) {}

  /// An empty array, or one holding `items` in order.
  static Json array(std::vector<Json> items = {});
  /// An empty object.
  static Json object();

  Type type() const { return type_; }
  bool is_null() const { return type_ == Type::Null; }

  /// The value; dem::InputError naming both types if it holds another type.
  bool as_bool() const;
  double as_number() const;
  const std::string& as_string() const;

  /// The member `key` of an object, appended as null if missing (then assign to it). A null
  /// value first becomes an empty object, so `Json summary; summary["balls"] = 1736;` works.
  /// Any other type is a dem::InputError.
  Json& operator[](const std::string& key);
  /// The member `key` of an object; dem::InputError listing the keys if there is none.
  const Json& at(const std::string& key) const;
  /// True if this is an object with member `key`.
  bool contains(const std::string& key) const;
  /// Object keys in insertion order (empty for other types).
  const std::vector<std::string>& keys() const { return keys_; }

  /// Appends to an array; a null value first becomes an empty array. Other types: InputError.
  void push_back(Json value);
  /// Element `index` of an array; dem::InputError if out of range or not an array.
  const Json& at(std::size_t index) const;
  /// Elements of an array, or values of an object in key order.
  const std::vector<Json>& items() const { return items_; }
  /// Elements of an array or members of an object; 0 for other types.
  std::size_t size() const { return items_.size(); }

  /// JSON text. indent > 0: one member or element per line, nested by `indent` spaces;
  /// indent == 0: everything on one line. Strings are escaped per RFC 8259 (quote, backslash
  /// and control characters; other UTF-8 passes through). Negative indent: dem::InputError.
  std::string dump(int indent = 2) const;
  /// Writes dump(indent) and a final newline to `path`, atomically (see atomic_file.hpp).
  void save(const std::filesystem::path& path, int indent = 2) const;

  /// Parses RFC 8259 JSON text (one value, surrounded by optional white space). Throws
  /// dem::InputError naming the line, column and problem for malformed text, numbers outside
  /// the range of a double, invalid escapes or lone UTF-16 surrogates, duplicate object keys,
  /// and nesting deeper than 512 levels.
  static Json parse(const std::string& text);
  /// Reads and parses a file; errors also name the file.
  static Json load(const std::filesystem::path& path);

  /// Same type and value; objects compare keys in order; numbers compare with == (so a NaN
  /// number, which dump writes as null, equals nothing).
  friend bool operator==(const Json& a, const Json& b);

 private:
  Type type_ = Type::Null;
  bool bool_ = false;
  double number_ = 0.0;
  std::string string_;
  std::vector<Json> items_;        // array elements, or object values parallel to keys_
  std::vector<std::string> keys_;  // object keys
};

}  // namespace dem::io
