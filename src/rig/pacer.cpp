#include "clearshape/rig/pacer.hpp"

#include <cmath>
#include <thread>

#include "clearshape/core/error.hpp"

namespace clearshape::rig {

Pacer::Pacer(double period_s) : period_s_(period_s) {
  require_in_half_open("period_s", period_s, 1e-9, 10.0 + 1e-12, "Pace at a rate above 0.1 Hz");
  period_ = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(period_s));
  if (period_.count() <= 0) period_ = Clock::duration(1);
}

void Pacer::start() noexcept {
  next_ = Clock::now();
  started_ = true;
  stats_ = PacerStats{};
}

Status Pacer::wait() noexcept {
  if (!started_) return Status::not_ready;
  ++stats_.cycles;
  const auto now = Clock::now();
  Status status = Status::ok;
  if (now > next_) {
    const auto late = now - next_;
    const double late_s = std::chrono::duration<double>(late).count();
    stats_.max_lateness_s = std::max(stats_.max_lateness_s, late_s);
    // A deadline met to within a microsecond (the first cycle, clock granularity) is on time.
    if (late > std::chrono::microseconds(1)) {
      status = Status::overrun;
      ++stats_.overruns;
      const auto missed = static_cast<std::uint64_t>(late / period_);
      stats_.missed_periods += missed;
      next_ += period_ * static_cast<Clock::rep>(missed);  // skip whole missed periods
    }
  } else {
    std::this_thread::sleep_until(next_);
  }
  next_ += period_;
  return status;
}

}  // namespace clearshape::rig
