#include "clearshape/rig/rig.hpp"

namespace clearshape::rig {

Status Rig::configure() {
  if (state_ != LifecycleState::unconfigured) return Status::not_ready;
  on_configure();  // throws on a bad configuration; the state stays unconfigured
  state_ = LifecycleState::inactive;
  return Status::ok;
}

Status Rig::activate() {
  if (state_ != LifecycleState::inactive) return Status::not_ready;
  on_activate();
  counters_ = CycleCounters{};
  state_ = LifecycleState::active;
  return Status::ok;
}

Status Rig::deactivate() {
  if (state_ != LifecycleState::active && state_ != LifecycleState::error) return Status::not_ready;
  on_deactivate();
  state_ = LifecycleState::inactive;
  return Status::ok;
}

Status Rig::cleanup() {
  if (state_ != LifecycleState::inactive) return Status::not_ready;
  on_cleanup();
  state_ = LifecycleState::unconfigured;
  return Status::ok;
}

Status Rig::read(Measurement& measurement) noexcept {
  const Status status = state_ == LifecycleState::active ? on_read(measurement) : Status::not_ready;
  ++counters_.reads;
  counters_.last_read = status;
  if (status != Status::ok) ++counters_.failed_reads;
  if (status == Status::device_error) state_ = LifecycleState::error;
  return status;
}

Status Rig::write(const Command& command) noexcept {
  const Status status = state_ == LifecycleState::active ? on_write(command) : Status::not_ready;
  ++counters_.writes;
  counters_.last_write = status;
  if (status != Status::ok) ++counters_.failed_writes;
  if (status == Status::device_error) state_ = LifecycleState::error;
  return status;
}

}  // namespace clearshape::rig
