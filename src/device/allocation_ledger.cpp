#include "device/allocation_ledger.hpp"

#include <algorithm>
#include <map>

namespace dipc::device {

void AllocationLedger::add(const void* p, std::size_t bytes, const char* what) {
  if (!p) return;
  std::lock_guard<std::mutex> lock(mutex_);
  live_[p] = {what ? what : "unnamed", bytes};
}

void AllocationLedger::remove(const void* p) {
  if (!p) return;
  std::lock_guard<std::mutex> lock(mutex_);
  live_.erase(p);
}

std::vector<AllocationLedger::Use> AllocationLedger::uses() const {
  std::map<std::string, Use> by_name;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [p, entry] : live_) {
      Use& u = by_name[entry.first];
      u.what = entry.first;
      u.bytes += entry.second;
      ++u.allocations;
    }
  }
  std::vector<Use> out;
  for (auto& [name, u] : by_name) out.push_back(std::move(u));
  std::stable_sort(out.begin(), out.end(), [](const Use& a, const Use& b) { return a.bytes > b.bytes; });
  return out;
}

std::size_t AllocationLedger::total_bytes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::size_t total = 0;
  for (const auto& [p, entry] : live_) total += entry.second;
  return total;
}

std::string AllocationLedger::per_element(std::size_t elements, std::size_t most) const {
  const std::vector<Use> all = uses();
  const double n = static_cast<double>(std::max<std::size_t>(elements, 1));
  std::size_t total = 0, rest = 0;
  for (const Use& u : all) total += u.bytes;
  auto rounded = [&](std::size_t bytes) { return std::to_string(static_cast<long long>(bytes / n + 0.5)); };
  std::string text = rounded(total) + " B/element";
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (i < most)
      text += (i ? ", " : ": ") + all[i].what + " " + rounded(all[i].bytes);
    else
      rest += all[i].bytes;
  }
  if (all.size() > most) text += ", " + std::to_string(all.size() - most) + " more " + rounded(rest);
  return text;
}

AllocationLedger& allocation_ledger() {
  static AllocationLedger ledger;
  return ledger;
}

}  // namespace dipc::device
