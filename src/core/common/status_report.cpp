#include "icanc/core/common/status_report.hpp"

namespace icanc {

void StatusReport::mergeSummary(StatusLevel l, const std::string& text) {
  if (l > StatusLevel::kOk && level > StatusLevel::kOk) {
    if (!message.empty()) message += "; ";
    message += text;
  } else if (l > level) {
    message = text;
  }
  if (l > level) level = l;
}

std::string StatusReport::value(const std::string& key) const {
  for (const auto& kv : values)
    if (kv.first == key) return kv.second;
  return "";
}

}  // namespace icanc
