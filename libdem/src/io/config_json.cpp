#include "config_json.hpp"

#include <cstddef>
#include <iterator>
#include <optional>
#include <set>

#include <nlohmann/json.hpp>

#include "dem/core/errors.hpp"
#include "dem/io/config.hpp"

namespace dem::io {
namespace {

using Json = nlohmann::ordered_json;

// Reads the text for the parser and counts the lines it has read: the line of an event.
class LineCountingIterator {
 public:
  using iterator_category = std::forward_iterator_tag;
  using value_type = char;
  using difference_type = std::ptrdiff_t;
  using pointer = const char*;
  using reference = const char&;

  LineCountingIterator(const char* at, std::size_t* line) : at_(at), line_(line) {}
  reference operator*() const { return *at_; }
  LineCountingIterator& operator++() {
    if (*at_ == '\n') ++*line_;
    ++at_;
    return *this;
  }
  LineCountingIterator operator++(int) {
    LineCountingIterator before = *this;
    ++*this;
    return before;
  }
  bool operator==(const LineCountingIterator& other) const { return at_ == other.at_; }
  bool operator!=(const LineCountingIterator& other) const { return at_ != other.at_; }

 private:
  const char* at_;
  std::size_t* line_;
};

// The SAX events of the parser, turned into assignments. Objects nest into key paths; arrays
// collect number texts. Deeper than max_config_depth nothing is kept, only the depth counted, so
// that the refusal names how deep the file goes.
class SettingsReader : public nlohmann::json_sax<Json> {
 public:
  SettingsReader(const std::string& where, const std::size_t& line) : where_(where), line_(line) {}

  bool null() override { return value("null", false); }
  bool boolean(bool v) override { return value(v ? "true" : "false", true); }
  bool number_integer(number_integer_t v) override { return value(std::to_string(v), true); }
  bool number_unsigned(number_unsigned_t v) override { return value(std::to_string(v), true); }
  bool number_float(number_float_t, const string_t& text) override { return value(text, true); }
  bool string(string_t& v) override { return value(v, false); }
  bool binary(binary_t&) override { return value("", false); }

  bool start_object(std::size_t) override {
    if (!open("section")) return true;
    if (list_) return skip("config key '" + *list_ + "': list elements must be numbers");
    levels_.push_back({pending_key_, {}});
    pending_key_.clear();
    return true;
  }
  bool end_object() override {
    if (close()) levels_.pop_back();
    return true;
  }
  bool key(string_t& name) override {
    if (ignoring()) return true;
    Level& level = levels_.back();
    const std::string full = level.path.empty() ? name : level.path + "." + name;
    if (!level.names.insert(name).second) duplicate_ = {full, line_};
    pending_key_ = full;
    return true;
  }
  bool start_array(std::size_t) override {
    if (!open("key")) return true;
    if (list_) return skip("config key '" + *list_ + "': list elements must be numbers");
    if (levels_.empty()) return skip("a list found where named keys were expected, at 'top level'");
    list_ = pending_key_;
    list_text_.clear();
    return true;
  }
  bool end_array() override {
    if (close()) {
      assign(*list_, list_text_);
      list_.reset();
    }
    return true;
  }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception& e) override {
    require_shallow();
    std::string message = e.what();
    const auto cut = message.find("syntax error");  // drop "[json.exception.parse_error.101] parse error at line 1, column 2: "
    if (cut != std::string::npos) message = message.substr(cut);
    throw InputError(where_ + "line " + std::to_string(line_) + ": " + message);
  }

  /// After the parse: the refusals the whole file had to be read for, then the assignments.
  std::vector<std::pair<std::string, std::string>> result() {
    require_shallow();
    if (refusal_) throw InputError(where_ + *refusal_);
    return std::move(settings_);
  }

 private:
  struct Level {
    std::string path;             // "section" or "" at the top
    std::set<std::string> names;  // of this object's keys so far
  };

  // A value after a key (or in a list): a leaf.
  bool value(const std::string& text, bool number) {
    if (ignoring()) return true;
    check_duplicate("key");
    if (list_) {
      if (!number) return refuse("config key '" + *list_ + "': list elements must be numbers");
      list_text_ += (list_text_.empty() ? "" : ",") + text;
      return true;
    }
    if (levels_.empty()) return refuse("a configuration file is a JSON object of sections, not a single value");
    assign(pending_key_, text);
    return true;
  }
  // Nothing is kept beyond max_config_depth, nor inside a container already refused.
  bool ignoring() const { return depth_ > max_config_depth || (skip_from_ != 0 && depth_ >= skip_from_); }
  // Returns false when the new level is not kept.
  bool open(const char* what) {
    if (!ignoring()) check_duplicate(what);
    const bool ignored = ignoring();
    ++depth_;
    if (depth_ > deepest_) deepest_ = depth_;
    if (depth_ > max_config_depth && deep_line_ == 0) deep_line_ = line_;
    return !ignored && depth_ <= max_config_depth;
  }
  // Returns true when the level closed was a kept one.
  bool close() {
    const bool kept = !ignoring();
    if (skip_from_ == depth_) skip_from_ = 0;
    --depth_;
    return kept;
  }
  // Refuses the container just opened and ignores what it holds.
  bool skip(const std::string& why) {
    skip_from_ = depth_;
    return refuse(why);
  }
  void check_duplicate(const char* what) {
    if (!duplicate_) return;
    throw InputError(where_ + "line " + std::to_string(duplicate_->second) + ": duplicate " + what + " name '" +
                     duplicate_->first + "': each " + what + " may appear once");
  }
  void assign(const std::string& key, const std::string& text) {
    if (!keys_.insert(key).second) refuse("duplicate key name '" + key + "': each key may be set once in a file");
    settings_.emplace_back(key, text);
  }
  bool refuse(const std::string& why) {
    if (!refusal_) refusal_ = why;
    return true;
  }
  void require_shallow() const {
    if (deepest_ > max_config_depth)
      throw InputError(where_ + "line " + std::to_string(deep_line_) + ": nesting depth " + std::to_string(deepest_) +
                       ": must be at most " + std::to_string(max_config_depth) +
                       " levels of objects and arrays (a configuration is section.key)");
  }

  const std::string& where_;
  const std::size_t& line_;
  std::vector<Level> levels_;
  std::size_t depth_ = 0, deepest_ = 0, deep_line_ = 0;
  std::size_t skip_from_ = 0;  // depth of a refused container (0: none)
  std::string pending_key_;
  std::optional<std::pair<std::string, std::size_t>> duplicate_;  // key, line: refused by what follows it
  std::optional<std::string> list_;  // key of the list being read
  std::string list_text_;
  std::set<std::string> keys_;
  std::optional<std::string> refusal_;  // the first problem of content, reported after the parse
  std::vector<std::pair<std::string, std::string>> settings_;
};

}  // namespace

std::vector<std::pair<std::string, std::string>> read_json_settings(const std::string& text, const std::string& where) {
  std::size_t line = 1;
  SettingsReader reader(where, line);
  Json::sax_parse(LineCountingIterator(text.data(), &line), LineCountingIterator(text.data() + text.size(), &line), &reader);
  return reader.result();
}

}  // namespace dem::io
