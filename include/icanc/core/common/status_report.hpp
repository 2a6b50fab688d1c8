// A diagnostic status without ROS: a level, a summary and key/value pairs, the values written as
// diagnostic_updater writes them (operator<<, booleans as True/False). A core class says in one
// what its nodelet reports; the nodelet copies it into /diagnostics (icanc/ros/nodelet_support.hpp,
// report()), and a gtest reads it.
#pragma once

#include <cstdint>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace icanc {

enum class StatusLevel : std::uint8_t { kOk = 0, kWarn = 1, kError = 2 };

struct StatusReport {
  StatusLevel level = StatusLevel::kOk;
  std::string message;
  std::vector<std::pair<std::string, std::string>> values;

  void summary(StatusLevel l, const std::string& text) {
    level = l;
    message = text;
  }
  // diagnostic_updater's mergeSummary: two problems (WARN or ERROR) join with "; ", else the
  // higher level's message stands.
  void mergeSummary(StatusLevel l, const std::string& text);

  template <class T>
  void add(const std::string& key, const T& value) {
    std::ostringstream ss;
    ss << value;
    values.emplace_back(key, ss.str());
  }
  void add(const std::string& key, bool value) { values.emplace_back(key, value ? "True" : "False"); }
  void add(const std::string& key, const std::string& value) { values.emplace_back(key, value); }

  // The value under `key`, "" when absent (for tests).
  std::string value(const std::string& key) const;
};

// Adds a value a kind, "<prefix><kind>" with the kind named by its toString, to `stat` (a
// StatusReport or a diagnostic_updater status: anything with add(key, value)), in the map's order;
// returns the counts' sum.
template <class Stat, class Kind>
std::uint64_t addCountsByKind(Stat& stat, const std::string& prefix,
                              const std::map<Kind, std::uint64_t>& counts) {
  std::uint64_t sum = 0;
  for (const auto& kv : counts) {
    sum += kv.second;
    stat.add(prefix + toString(kv.first), kv.second);
  }
  return sum;
}

// Fault counters (each only grows) in the order their kinds name a status: which kind grew since
// the last report. A diagnostics report WARNs with the first that did, then OK again once none
// grows.
class FaultGrowth {
 public:
  // The index of the first count above the one seen at the last call, or -1; the counts are kept.
  int firstGrown(const std::vector<std::uint64_t>& counts) {
    seen_.resize(counts.size(), 0);
    int first = -1;
    for (std::size_t i = 0; i < counts.size(); ++i) {
      if (first < 0 && counts[i] > seen_[i]) first = static_cast<int>(i);
      seen_[i] = counts[i];
    }
    return first;
  }

 private:
  std::vector<std::uint64_t> seen_;
};

}  // namespace icanc
