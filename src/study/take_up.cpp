#include "clearshape/study/take_up.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <Eigen/Core>
#include <Eigen/LU>
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

// The two conditions of a take-up (header) as residuals of the carry and dip velocities x:
// tangency at contact (relative to the move's mean rate θ/T) and the take-up equal to the play.
struct TakeUpConditions {
  using Scalar = double;
  enum { NUM_RESIDUALS = 2, NUM_PARAMETERS = 2 };

  const TakeUpRequest* request = nullptr;
  double theta_deg = 0.0, play_deg = 0.0, alpha_deg_s2 = 0.0, lead_deg_s = 0.0;
  double dt_s = 0.0, horizon_s = 0.0;

  TakeUpConditions(const TakeUpRequest& r, double move_deg, double lead)
      : request(&r), theta_deg(std::abs(move_deg)), play_deg(rad_to_deg(r.model.play_rad)),
        alpha_deg_s2(rad_to_deg(flank_keeping_deceleration_rad_s2(r.model))), lead_deg_s(lead) {
    const double T = r.grid_s;
    dt_s = T / std::ceil(T / 1e-4);
    horizon_s = (static_cast<double>(lead_slots()) + 3.0 + 6.0) * T + 10.0 * r.model.drive.delay_s();
  }
  std::size_t lead_slots() const { return lead_deg_s > 0.0 ? 1 : 0; }
  double mean_rate() const { return theta_deg / request->grid_s; }
  /// Lead (if any), carry, dip, recover: the recover slot is the move's remainder (T·Σv = θ).
  std::vector<double> slots(const double* x) const {
    std::vector<double> v;
    if (lead_slots()) v.push_back(lead_deg_s);
    v.push_back(x[0]);
    v.push_back(x[1]);
    v.push_back(mean_rate() - lead_deg_s - x[0] - x[1]);
    return v;
  }
  Kinematics kinematics_of(const double* x) const {
    const std::vector<double> w = drive_rate_response(request->model.drive, slots(x), request->grid_s, dt_s, horizon_s);
    return kinematics(w, dt_s, alpha_deg_s2);
  }
  void residuals(const double* x, double* f) const {
    const Kinematics k = kinematics_of(x);
    f[0] = k.tangency / mean_rate();
    f[1] = (k.take_up - play_deg) / play_deg;
  }
  /// Residuals and their forward-difference Jacobian (column-major, 2 × 2).
  bool operator()(const double* x, double* f, double* jacobian) const {
    residuals(x, f);
    if (!jacobian) return true;
    const double h = 1e-4 * mean_rate();
    for (int j = 0; j < NUM_PARAMETERS; ++j) {
      double xh[2] = {x[0], x[1]};
      xh[j] += h;
      double fh[2];
      residuals(xh, fh);
      for (int i = 0; i < NUM_RESIDUALS; ++i) jacobian[j * NUM_RESIDUALS + i] = (fh[i] - f[i]) / h;
    }
    return true;
  }
};

// Solves the two conditions by Newton's method with step halving (2 unknowns, forward-difference
// Jacobian) from the closed form of a pure-delay drive (header): v_c = v_r, (v_c − v_d)·T = 2β.
// Ceres' TinySolver (Levenberg–Marquardt) was tried here and stalls at 56° (residual 99): the
// kinematics' peak indices make the residual piecewise smooth, and the full Newton step from the
// closed form is what crosses those seams.
std::pair<Eigen::Vector2d, int> solve_conditions(const TakeUpConditions& c) {
  const double T = c.request->grid_s;
  const double carry0 = (c.theta_deg - c.lead_deg_s * T + c.play_deg) / (3.0 * T);
  Eigen::Vector2d x(carry0, carry0 - c.play_deg / T);
  Eigen::Vector2d f;
  Eigen::Matrix2d jacobian;
  c(x.data(), f.data(), jacobian.data());
  int it = 0;
  for (; it < 60 && f.norm() > 1e-7; ++it) {
    const Eigen::Vector2d step = jacobian.partialPivLu().solve(-f);
    if (!step.allFinite()) break;
    bool improved = false;
    for (double lambda = 1.0; lambda > 1e-6 && !improved; lambda *= 0.5) {
      Eigen::Vector2d xn = x + lambda * step, fn;
      c.residuals(xn.data(), fn.data());
      if (fn.norm() < f.norm()) {
        x = xn;
        improved = true;
      }
    }
    if (!improved) break;
    c(x.data(), f.data(), jacobian.data());
  }
  return {x, it};
}

// Why a solved profile cannot be used, or "" when it can.
std::string unusable(const TakeUpConditions& c, const Eigen::Vector2d& x, const std::vector<double>& v) {
  double f[2];
  c.residuals(x.data(), f);
  const double norm = std::hypot(f[0], f[1]);
  if (norm > 1e-4) {
    return fmt::format("the tangency and take-up conditions have no solution near the closed form (residual {:.3g})",
                       norm);
  }
  if (*std::min_element(v.begin(), v.end()) < 0.0) return "the dip would need a reverse velocity";
  if (c.lead_slots() && !(x[0] > c.lead_deg_s)) {
    return fmt::format("the carry ({:.4g} deg/s) is not faster than the lead ({:.4g} deg/s)", x[0], c.lead_deg_s);
  }
  return {};
}

Attempt solve(const TakeUpRequest& r, double move_deg, double lead) {
  const TakeUpConditions c(r, move_deg, lead);
  const auto [x, iterations] = solve_conditions(c);
  const std::vector<double> v = c.slots(x.data());
  Attempt a;
  a.why = unusable(c, x, v);
  if (!a.why.empty()) return a;
  a.ok = true;
  const Kinematics k = c.kinematics_of(x.data());
  TakeUpMove& m = a.move;
  m.move_deg = move_deg;
  m.slot_velocity_deg_s = v;
  std::vector<shaping::Impulse> impulses;
  for (std::size_t s = 0; s < v.size(); ++s) {
    if (v[s] > 0.0) impulses.push_back({static_cast<double>(s) * r.grid_s, v[s] * r.grid_s / c.theta_deg});  // a_k = v_k·T/θ
  }
  m.shaper = shaping::Shaper("take-up", std::move(impulses));
  m.separation_s = k.t1;
  m.contact_s = k.t2;
  m.link_rate_deg_s = k.link_rate;
  m.take_up_deg = k.take_up;
  m.contact_relative_rate_deg_s = -k.tangency;
  m.overtake_deg_s = k.overtake;
  m.reversal_deg_s = k.reversal;
  m.iterations = iterations;
  return a;
}

}  // namespace

nlohmann::ordered_json take_up_move_json(const TakeUpMove& m) {
  nlohmann::ordered_json impulses = nlohmann::ordered_json::array();
  for (const auto& i : m.shaper.impulses()) impulses.push_back({{"time_s", i.time_s}, {"amplitude", i.amplitude}});
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
