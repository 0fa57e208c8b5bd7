// Latencies in 0.1 ms bins up to 2 s (beyond: the last bin): percentiles in constant memory
// over a status period or a whole run. Not thread-safe; its owner locks.
#pragma once

#include "io/lcm/bus.h"

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

namespace saccade {

class LatencyHistogram {
 public:
  std::int64_t count() const { return count_; }
  void Add(double ms) {
    const auto bin = static_cast<std::size_t>(std::max(0.0, ms) * 10);
    ++bins_[std::min(bin, bins_.size() - 1)];
    ++count_;
    max_ms_ = std::max(max_ms_, ms);
  }
  /// The q-quantile (q in [0, 1]) to the bin's centre, ms; 0 when empty.
  double Percentile(double q) const {
    if (count_ == 0) return 0;
    const auto rank = static_cast<std::int64_t>(q * (count_ - 1));
    std::int64_t seen = 0;
    for (std::size_t i = 0; i < bins_.size(); ++i) {
      seen += bins_[i];
      if (seen > rank) return (i + 0.5) / 10;
    }
    return bins_.size() / 10.0;
  }
  /// The period's report, then empty for the next period.
  LatencyReport TakeReport(const std::string& name) {
    LatencyReport r;
    r.name = name;
    r.samples = static_cast<int>(count_);
    r.p50_ms = static_cast<float>(Percentile(0.5));
    r.p90_ms = static_cast<float>(Percentile(0.9));
    r.p99_ms = static_cast<float>(Percentile(0.99));
    r.max_ms = static_cast<float>(max_ms_);
    *this = LatencyHistogram();
    return r;
  }

 private:
  std::vector<std::int64_t> bins_ = std::vector<std::int64_t>(20000, 0);
  std::int64_t count_ = 0;
  double max_ms_ = 0;
};

}  // namespace saccade
