#include "clearshape/study/take_up.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/lti/simulate.hpp"

namespace clearshape::study {

double flank_keeping_deceleration_rad_s2(const ClearanceModel& model) noexcept {
  // Newton on the coasting link: J·dω/dt = −c (Coulomb, sliding), so |a| <= c/J keeps contact.
  if (!(model.link_inertia_kg_m2 > 0.0) || !(model.coulomb_n_m > 0.0)) return 0.0;
  return model.coulomb_n_m / model.link_inertia_kg_m2;
}

double flank_keeping_move_time_s(double move_rad, double a_rad_s2) noexcept {
  if (!(a_rad_s2 > 0.0)) return std::numeric_limits<double>::infinity();
  return 2.0 * std::sqrt(std::abs(move_rad) / a_rad_s2);  // θ/2 = a(t/2)²/2 on each half
}

void TakeUpRequest::validate() const {
  if (model.mode != rig::CommandMode::position) {
    throw InvalidArgument("model.mode: take-up is designed on the position command path (30 Hz velocity slots); "
                          "the model is speed mode");
  }
  if (!(model.play_rad > 0.0)) throw InvalidArgument("model.play_rad: the model has no play; nothing to take up");
  require_positive("model.link_inertia_kg_m2", model.link_inertia_kg_m2);
  if (moves.empty()) throw InvalidArgument("moves: give at least one step amplitude");
  for (const double m : moves) {
    require_finite("moves", m);
    if (m == 0.0) throw InvalidArgument("moves: a step amplitude of 0 is no move; give non-zero amplitudes");
  }
  require_in_closed("grid_s", grid_s, 1e-3, 1.0);
  if (!(max_duration_s >= 2.0 * grid_s - 1e-9) || !(max_duration_s <= 5.0)) {
    throw_invalid("max_duration_s", max_duration_s, fmt::format("[{:.6g}, 5] s", 2.0 * grid_s),
                  "A take-up needs three updates (carry, dip, recover); a fourth adds the lead slot");
  }
  require_finite("lead_velocity_deg_s", lead_velocity_deg_s);
}

std::vector<double> drive_rate_response(const lti::ProcessModel& drive, const std::vector<double>& slots,
                                        double grid_s, double sample_time_s, double duration_s) {
  require_positive("sample_time_s", sample_time_s);
  require_positive("duration_s", duration_s);
  const auto n = static_cast<std::size_t>(std::floor(duration_s / sample_time_s + 1e-9)) + 1;
  UniformSeries rate{0.0, sample_time_s, std::vector<double>(n, 0.0)};
  for (std::size_t i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(std::floor(static_cast<double>(i) * sample_time_s / grid_s + 1e-9));
    rate.values[i] = k < slots.size() ? slots[k] : 0.0;
  }
  // Position mode: the drive maps command deg → motor deg; by linearity and time invariance the
  // same transfer maps the command's rate to the motor's rate (held per sample: exact for slots).
  return lti::simulate(drive, rate, lti::Hold::zoh).values;
}

namespace {

struct Kinematics {
  double t1 = 0.0, t2 = 0.0, link_rate = 0.0, take_up = 0.0, tangency = 0.0, overtake = 0.0, reversal = 0.0;
};

// The link leaves the rear flank at the motor rate's first peak t₁ and coasts, decelerated by its
// friction α (deg/s²); t₂ is the next peak of ω (after its dip).
Kinematics kinematics(const std::vector<double>& w, double dt, double alpha) {
  Kinematics k;
  const std::size_t n = w.size();
  std::size_t i1 = 1;
  while (i1 + 1 < n && !(w[i1] >= w[i1 - 1] && w[i1] > w[i1 + 1])) ++i1;
  std::size_t i2 = i1;
  while (i2 + 1 < n && w[i2 + 1] <= w[i2]) ++i2;  // down the dip
  while (i2 + 1 < n && w[i2 + 1] > w[i2]) ++i2;   // up to the second peak
  k.t1 = static_cast<double>(i1) * dt;
  k.t2 = static_cast<double>(i2) * dt;
  k.link_rate = w[i1];
  const auto link = [&](std::size_t i) { return w[i1] - alpha * (static_cast<double>(i - i1) * dt); };
  for (std::size_t i = i1; i < i2; ++i) {  // trapezoid rule
    k.take_up += 0.5 * dt * ((link(i) - w[i]) + (link(i + 1) - w[i + 1]));
  }
  k.tangency = w[i2] - link(i2);
  for (std::size_t i = i2 + 1; i < n; ++i) {
    k.overtake = std::max(k.overtake, w[i] - std::max(0.0, link(i)));
    k.reversal = std::max(k.reversal, -w[i]);
  }
  return k;
}

struct Attempt {
  bool ok = false;
  std::string why;
  TakeUpMove move;
};

Attempt solve(const TakeUpRequest& r, double move_deg, double lead) {
  const double theta = std::abs(move_deg);
  const double play = rad_to_deg(r.model.play_rad);
  const double alpha = rad_to_deg(flank_keeping_deceleration_rad_s2(r.model));
  const double T = r.grid_s;
  const auto sub = static_cast<int>(std::ceil(T / 1e-4));
  const double dt = T / sub;
  const std::size_t lead_slots = lead > 0.0 ? 1 : 0;
  const double horizon = (static_cast<double>(lead_slots) + 3.0 + 6.0) * T + 10.0 * r.model.drive.delay_s();
  const auto slots_of = [&](const std::array<double, 2>& x) {
    std::vector<double> v;
    if (lead_slots) v.push_back(lead);
    v.push_back(x[0]);
    v.push_back(x[1]);
    v.push_back(theta / T - lead - x[0] - x[1]);  // recover: the move's remainder (T·Σv = θ)
    return v;
  };
  const auto residual = [&](const std::array<double, 2>& x, Kinematics* out = nullptr) {
    const Kinematics k = kinematics(drive_rate_response(r.model.drive, slots_of(x), T, dt, horizon), dt, alpha);
    if (out) *out = k;
    return std::array<double, 2>{k.tangency / (theta / T), (k.take_up - play) / play};
  };
  const auto norm = [](const std::array<double, 2>& f) { return std::hypot(f[0], f[1]); };
  // The closed form of a pure-delay drive (header): v_c = v_r, (v_c − v_d)·T = 2β.
  const double carry0 = (theta - lead * T + play) / (3.0 * T);
  std::array<double, 2> x{carry0, carry0 - play / T};
  std::array<double, 2> f = residual(x);
  int it = 0;
  for (; it < 60 && norm(f) > 1e-7; ++it) {
    double jac[2][2];
    for (int j = 0; j < 2; ++j) {
      std::array<double, 2> xh = x;
      const double h = 1e-4 * theta / T;
      xh[static_cast<std::size_t>(j)] += h;
      const auto fh = residual(xh);
      jac[0][j] = (fh[0] - f[0]) / h;
      jac[1][j] = (fh[1] - f[1]) / h;
    }
    const double det = jac[0][0] * jac[1][1] - jac[0][1] * jac[1][0];
    if (!(std::abs(det) > 0.0)) break;
    const std::array<double, 2> step{(-f[0] * jac[1][1] + f[1] * jac[0][1]) / det,
                                     (-f[1] * jac[0][0] + f[0] * jac[1][0]) / det};
    double lambda = 1.0;
    bool improved = false;
    for (int halving = 0; halving < 20; ++halving, lambda *= 0.5) {
      const std::array<double, 2> xn{x[0] + lambda * step[0], x[1] + lambda * step[1]};
      const auto fn = residual(xn);
      if (norm(fn) < norm(f)) {
        x = xn;
        f = fn;
        improved = true;
        break;
      }
    }
    if (!improved) break;
  }
  Attempt a;
  Kinematics k;
  f = residual(x, &k);
  const std::vector<double> v = slots_of(x);
  if (norm(f) > 1e-4) {
    a.why = fmt::format("the tangency and take-up conditions have no solution near the closed form (residual {:.3g})",
                        norm(f));
    return a;
  }
  if (*std::min_element(v.begin(), v.end()) < 0.0) {
    a.why = "the dip would need a reverse velocity";
    return a;
  }
  if (lead_slots && !(x[0] > lead)) {
    a.why = fmt::format("the carry ({:.4g} deg/s) is not faster than the lead ({:.4g} deg/s)", x[0], lead);
    return a;
  }
  a.ok = true;
  TakeUpMove& m = a.move;
  m.move_deg = move_deg;
  m.slot_velocity_deg_s = v;
  std::vector<shaping::Impulse> impulses;
  for (std::size_t s = 0; s < v.size(); ++s) {
    if (v[s] > 0.0) impulses.push_back({static_cast<double>(s) * T, v[s] * T / theta});  // a_k = v_k·T/θ
  }
  m.shaper = shaping::Shaper("take-up", std::move(impulses));
  m.separation_s = k.t1;
  m.contact_s = k.t2;
  m.link_rate_deg_s = k.link_rate;
  m.take_up_deg = k.take_up;
  m.contact_relative_rate_deg_s = -k.tangency;
  m.overtake_deg_s = k.overtake;
  m.reversal_deg_s = k.reversal;
  m.iterations = it;
  return a;
}

}  // namespace

nlohmann::ordered_json take_up_move_json(const TakeUpMove& m) {
  nlohmann::ordered_json impulses = nlohmann::ordered_json::array();
  for (const auto& i : m.shaper.impulses()) impulses.push_back({{"t", i.time_s}, {"a", i.amplitude}});
  return {{"move_deg", m.move_deg}, {"impulses", impulses}, {"slot_velocity_deg_s", m.slot_velocity_deg_s},
          {"separation_s", m.separation_s}, {"contact_s", m.contact_s}, {"link_rate_deg_s", m.link_rate_deg_s},
          {"take_up_deg", m.take_up_deg}, {"contact_relative_rate_deg_s", m.contact_relative_rate_deg_s},
          {"overtake_deg_s", m.overtake_deg_s}, {"reversal_deg_s", m.reversal_deg_s}};
}

TakeUpResult design_take_up(const TakeUpRequest& request) {
  request.validate();
  const double play_deg = rad_to_deg(request.model.play_rad);
  const bool room_for_lead = request.max_duration_s >= 3.0 * request.grid_s - 1e-9;
  const double lead = !room_for_lead ? 0.0
                      : request.lead_velocity_deg_s < 0.0 ? play_deg / request.grid_s  // header: 2β/T
                                                          : request.lead_velocity_deg_s;
  TakeUpResult result;
  result.flank_keeping_deceleration_rad_s2 = flank_keeping_deceleration_rad_s2(request.model);
  for (const double move : request.moves) {
    Attempt a = solve(request, move, lead);
    if (!a.ok && lead > 0.0 && request.lead_velocity_deg_s < 0.0) a = solve(request, move, 0.0);  // default lead only
    if (!a.ok) {
      throw InvalidArgument(fmt::format(
          "moves: no take-up profile for {:g} deg with {:.4g} deg of play on a {:.4g} s grid: {}; the shortest move "
          "it can take up is about {:.3g} deg (2 × play{})",
          move, play_deg, request.grid_s, a.why, 2.0 * play_deg + (lead > 0.0 ? lead * request.grid_s : 0.0),
          lead > 0.0 ? " + the lead slot's travel" : ""));
    }
    result.moves.push_back(std::move(a.move));
    result.flank_keeping_move_time_s.push_back(
        flank_keeping_move_time_s(deg_to_rad(move), result.flank_keeping_deceleration_rad_s2));
  }
  return result;
}

}  // namespace clearshape::study
