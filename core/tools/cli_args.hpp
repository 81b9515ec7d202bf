#pragma once
// Minimal "--key value" / "--flag" parsing for the CLI subcommands, with unknown options rejected.
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace pslam {

class CliArgs {
 public:
  explicit CliArgs(std::vector<std::string> args) : args_(std::move(args)) {}

  std::optional<std::string> Value(const std::string& key) {
    known_.insert(key);
    for (std::size_t i = 0; i < args_.size(); ++i) {
      if (args_[i] != key) continue;
      if (i + 1 >= args_.size()) {
        error_ += "missing value after " + key + "\n";
        return std::nullopt;
      }
      return args_[i + 1];
    }
    return std::nullopt;
  }
  int Int(const std::string& key, int fallback) {
    const auto v = Value(key);
    if (!v) return fallback;
    try {
      std::size_t used = 0;
      const int n = std::stoi(*v, &used);
      if (used == v->size()) return n;
    } catch (const std::exception&) {
    }
    error_ += "not an integer: " + key + " " + *v + "\n";
    return fallback;
  }
  double Double(const std::string& key, double fallback) {
    const auto v = Value(key);
    if (!v) return fallback;
    try {
      std::size_t used = 0;
      const double d = std::stod(*v, &used);
      if (used == v->size()) return d;
    } catch (const std::exception&) {
    }
    error_ += "not a number: " + key + " " + *v + "\n";
    return fallback;
  }
  // Every value of a repeatable option, in order.
  std::vector<std::string> Values(const std::string& key) {
    known_.insert(key);
    std::vector<std::string> out;
    for (std::size_t i = 0; i + 1 < args_.size(); ++i) {
      if (args_[i] == key) out.push_back(args_[++i]);
    }
    return out;
  }
  void AddError(const std::string& message) { error_ += message + "\n"; }
  bool Flag(const std::string& key) {
    flags_.insert(key);
    for (const auto& a : args_) {
      if (a == key) return true;
    }
    return false;
  }
  // True when every argument was recognised and well-formed; call after all lookups.
  bool ok() {
    for (std::size_t i = 0; i < args_.size(); ++i) {
      if (flags_.count(args_[i])) continue;
      if (known_.count(args_[i])) {
        ++i;
        continue;
      }
      error_ += "unknown argument: " + args_[i] + "\n";
    }
    return error_.empty();
  }
  const std::string& error() const { return error_; }

 private:
  std::vector<std::string> args_;
  std::set<std::string> known_, flags_;
  std::string error_;
};

}  // namespace pslam
