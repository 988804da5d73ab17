// One declaration per configuration key: a binding table ties each key of a file section to the
// member of the struct that section is read into. The key is "<section>.<name>" with name = the
// member's name; the table row gives its unit, allowed range and help, and the default is the
// member's value in a default-constructed struct, so struct, schema and reading code cannot drift.
//
//   struct PlateConfig { double stiffness = 1e8; long steps = 100; };
//   const io::BindingTable<PlateConfig> plate_keys = {
//       {"stiffness", &PlateConfig::stiffness, "N/m", "plate stiffness", 0.0, {}, true},
//       {"steps", &PlateConfig::steps, "-", "steps per stage", 1.0}};
//   io::add_keys(schema, "plate", plate_keys, PlateConfig{});        // plate.stiffness, plate.steps
//   PlateConfig plate;
//   io::read_keys(config, "plate", plate_keys, plate);               // validated values
//
// A text key read into something that is not text (an enum, an optional number) is a TextChoice:
// its allowed words and the two conversions; enum_choice() makes one for an enum whose values are
// 0, 1, 2... in the order of the words.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <tuple>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include <dem/io/config.hpp>

namespace dem::io {

/// The shortest "%g" text (6 to 17 significant digits) that reads back to exactly `value`: how a
/// default is written in the schema and in --print-config's help.
std::string real_text(double value);
/// Comma-separated real_text of each value.
std::string real_list_text(const std::vector<double>& values);

template <class S>
struct TextChoice {
  std::vector<std::string> choices;  // allowed words; empty: any text that `set` accepts
  std::function<std::string(const S&)> get;
  /// Stores the text's value; throws InputError naming `key` for a text it cannot read.
  std::function<void(S&, const std::string& text, const std::string& key)> set;
};

/// A real reached through two functions: a member of a member (settings.comparison.eps_stress).
template <class S>
struct RealField {
  std::function<double(const S&)> get;
  std::function<void(S&, double)> set;
};

template <class S>
using BoundMember = std::variant<double S::*, long S::*, int S::*, std::uint64_t S::*, bool S::*, std::string S::*,
                                 std::vector<double> S::*, TextChoice<S>, RealField<S>>;

/// One key: `name` (the member's name), the member, its SI unit, help and range (of every element
/// for a list); integers and reals share the range; and when a resumed run may no longer change it
/// (none: the section's rule, add_keys). Field order allows {name, member, unit, help, min, max}.
template <class S>
struct Binding {
  std::string name;
  BoundMember<S> member;
  std::string unit;
  std::string help;
  std::optional<double> min{}, max{};
  bool min_exclusive = false;
  std::optional<FixedAfter> fixed{};
};

template <class S>
using BindingTable = std::vector<Binding<S>>;

/// A TextChoice for an enum field whose values are 0, 1, 2... in the order of `words`.
template <class S, class E>
TextChoice<S> enum_choice(std::vector<std::string> words, E S::*field) {
  return {words, [words, field](const S& s) { return words.at(static_cast<std::size_t>(s.*field)); },
          [words, field](S& s, const std::string& text, const std::string&) {
            for (std::size_t k = 0; k < words.size(); ++k)
              if (words[k] == text) s.*field = static_cast<E>(k);
          }};
}

/// The key type and the text of a row's member in `value`.
template <class S>
std::pair<ValueType, std::string> bound_text(const Binding<S>& binding, const S& value) {
  return std::visit(
      [&](const auto& m) -> std::pair<ValueType, std::string> {
        using M = std::decay_t<decltype(m)>;
        if constexpr (std::is_same_v<M, double S::*>) return {ValueType::Real, real_text(value.*m)};
        else if constexpr (std::is_same_v<M, bool S::*>) return {ValueType::Boolean, value.*m ? "true" : "false"};
        else if constexpr (std::is_same_v<M, std::string S::*>) return {ValueType::Text, value.*m};
        else if constexpr (std::is_same_v<M, std::vector<double> S::*>) return {ValueType::RealList, real_list_text(value.*m)};
        else if constexpr (std::is_same_v<M, TextChoice<S>>) return {ValueType::Text, m.get(value)};
        else if constexpr (std::is_same_v<M, RealField<S>>) return {ValueType::Real, real_text(m.get(value))};
        else return {ValueType::Integer, std::to_string(value.*m)};
      },
      binding.member);
}

/// Adds "<section>.<name>" for every row, with the default taken from `defaults` and the resume
/// rule of the row, or `section_rule` for a row without one.
template <class S>
void add_keys(Schema& schema, const std::string& section, const BindingTable<S>& table, const S& defaults,
              const std::optional<FixedAfter>& section_rule = std::nullopt) {
  for (const Binding<S>& b : table) {
    KeySpec spec{.key = section + "." + b.name, .unit = b.unit, .help = b.help, .min = b.min, .max = b.max,
                 .min_exclusive = b.min_exclusive, .fixed = b.fixed ? b.fixed : section_rule};
    std::tie(spec.type, spec.default_value) = bound_text(b, defaults);
    if (const auto* choice = std::get_if<TextChoice<S>>(&b.member)) spec.choices = choice->choices;
    schema.add(spec);
  }
}

/// Reads every row's key of `config` into `out`.
template <class S>
void read_keys(const Config& config, const std::string& section, const BindingTable<S>& table, S& out) {
  for (const Binding<S>& b : table) {
    const std::string key = section + "." + b.name;
    std::visit(
        [&](const auto& m) {
          using M = std::decay_t<decltype(m)>;
          if constexpr (std::is_same_v<M, double S::*>) out.*m = config.real(key);
          else if constexpr (std::is_same_v<M, bool S::*>) out.*m = config.boolean(key);
          else if constexpr (std::is_same_v<M, std::string S::*>) out.*m = config.text(key);
          else if constexpr (std::is_same_v<M, std::vector<double> S::*>) out.*m = config.real_list(key);
          else if constexpr (std::is_same_v<M, TextChoice<S>>) m.set(out, config.text(key), key);
          else if constexpr (std::is_same_v<M, RealField<S>>) m.set(out, config.real(key));
          else out.*m = static_cast<std::remove_reference_t<decltype(out.*m)>>(config.integer(key));
        },
        b.member);
  }
}

/// (key, text) of every row for the values in `value`, as a file would hold them: what a struct
/// made in C++ says in the configuration language (Config::set reads each back to the same value).
template <class S>
void append_values(std::vector<std::pair<std::string, std::string>>& out, const std::string& section,
                   const BindingTable<S>& table, const S& value) {
  for (const Binding<S>& b : table) out.emplace_back(section + "." + b.name, bound_text(b, value).second);
}

}  // namespace dem::io
