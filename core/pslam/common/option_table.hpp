#pragma once
// Options set by name from text (`--set NAME=VALUE`): each options struct keeps one table that maps
// a name to a setter of its member.
#include <charconv>
#include <functional>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

namespace pslam {

template <typename Options>
using OptionSetter = std::function<std::string(Options&, const std::string&)>;
template <typename Options>
using OptionTable = std::map<std::string, OptionSetter<Options>>;

// "" when `text` is a whole number (true/false/1/0 for a flag) and is stored in `out`; else what is wrong.
template <typename T>
std::string ParseOptionValue(const std::string& text, T& out) {
  if constexpr (std::is_same_v<T, bool>) {
    if (text == "true" || text == "1") out = true;
    else if (text == "false" || text == "0") out = false;
    else return "not a boolean: '" + text + "'";
    return "";
  } else {
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, out);
    if (ec != std::errc() || ptr != end) return "not a number: '" + text + "'";
    return "";
  }
}

// The setter of a member, or of a member of a member group ("insert.hit_probability").
template <typename Options, typename T>
OptionSetter<Options> Option(T Options::*member) {
  return [member](Options& o, const std::string& v) { return ParseOptionValue(v, o.*member); };
}
template <typename Options, typename Group, typename T>
OptionSetter<Options> Option(Group Options::*group, T Group::*member) {
  return [group, member](Options& o, const std::string& v) { return ParseOptionValue(v, (o.*group).*member); };
}

// "" once set; else "unknown KIND 'NAME'" or "NAME: what is wrong with the value".
template <typename Options>
std::string SetOption(const OptionTable<Options>& table, Options& options, const std::string& name,
                      const std::string& value, const std::string& kind = "option") {
  const auto it = table.find(name);
  if (it == table.end()) return "unknown " + kind + " '" + name + "'";
  const std::string error = it->second(options, value);
  return error.empty() ? "" : name + ": " + error;
}

template <typename Options>
std::vector<std::string> OptionNames(const OptionTable<Options>& table) {
  std::vector<std::string> names;
  for (const auto& [name, setter] : table) names.push_back(name);
  return names;
}

}  // namespace pslam
