// Starting points of the process-model fit (doc/sysid §4.4): step overshoot and peak time,
// a subspace model, a log-spaced grid; and the optimizer layout.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <string>

#include "clearshape/core/linalg.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/ident/subspace.hpp"
#include "process_detail.hpp"

namespace clearshape::ident::detail {

namespace {

bool iequals(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
         });
}

bool positive_parameter(std::string_view name) {
  return name == "Tp1" || name == "Tp2" || name == "Tp3" || name == "Tw" || name == "Zeta";
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// What a step record tells (sysid §4.4): gain, overshoot → ζ, peak time → ωd, 63 % time, onset.
struct StepSeed {
  double zeta = kNaN;
  double wn_rad_s = kNaN;
  double t63_s = kNaN;
  double onset_s = 0.0;  // first visible response after the step
};

std::optional<StepSeed> analyse_step(const Experiment& e) {
  const std::size_t n = e.size();
  // Step-like: one jump (history 0 before the record) carries ≥ 90 % of the total variation.
  double total = 0.0, best = 0.0;
  std::size_t k0 = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double jump = std::abs(e.input[k] - (k == 0 ? 0.0 : e.input[k - 1]));
    total += jump;
    if (jump > best) {
      best = jump;
      k0 = k;
    }
  }
  if (!(total > 0.0) || best < 0.9 * total || k0 + 20 > n) return std::nullopt;
  const double y_base = k0 == 0 ? e.output[0] : e.output[k0 - 1];
  double y_final = 0.0;
  const std::size_t tail = std::max<std::size_t>(1, (n - k0) / 10);
  for (std::size_t k = n - tail; k < n; ++k) y_final += e.output[k];
  y_final /= static_cast<double>(tail);
  const double dy = y_final - y_base;
  if (!(std::abs(dy) > 0.0)) return std::nullopt;
  const double sign = dy > 0.0 ? 1.0 : -1.0;
  const double t = e.sample_time_s;
  StepSeed s;
  double peak = -std::numeric_limits<double>::infinity();
  std::size_t k_peak = k0, k63 = n, k_onset = n;
  for (std::size_t k = k0; k < n; ++k) {
    const double v = (e.output[k] - y_base) * sign;
    if (v > peak) {
      peak = v;
      k_peak = k;
    }
    if (k63 == n && v >= 0.632 * std::abs(dy)) k63 = k;
    if (k_onset == n && std::abs(v) >= 0.03 * std::abs(dy)) k_onset = k;
  }
  s.onset_s = static_cast<double>(k_onset - k0) * t;
  if (k63 < n) s.t63_s = std::max(static_cast<double>(k63 - k0) * t, 2.0 * t);
  const double overshoot = peak / std::abs(dy) - 1.0;
  if (overshoot > 0.02 && k_peak > k0) {  // ζ = −ln Mp/√(π² + ln²Mp), ωd = π/tp
    const double l = std::log(overshoot);
    s.zeta = -l / std::sqrt(std::numbers::pi * std::numbers::pi + l * l);
    const double tp = std::max(static_cast<double>(k_peak - k0) * t, 2.0 * t);
    s.wn_rad_s = std::numbers::pi / tp / std::sqrt(1.0 - s.zeta * s.zeta);
  }
  return s;
}

// Continuous poles of N4SID models of the structure's order on block-averaged data.
std::vector<std::vector<std::complex<double>>> subspace_poles(const Experiment& e, int order) {
  std::vector<std::vector<std::complex<double>>> out;
  if (order < 1) return out;
  for (std::size_t q : {1, 4, 16, 64}) {  // 200 to 2500 averaged samples: enough, and cheap
    if (e.size() / q < 200) break;
    if (e.size() / q > 2500) continue;
    Experiment d;
    d.name = e.name;
    d.sample_time_s = e.sample_time_s * static_cast<double>(q);
    for (std::size_t k = 0; (k + 1) * q <= e.size(); ++k) {
      double su = 0.0, sy = 0.0;
      for (std::size_t j = 0; j < q; ++j) {
        su += e.input[k * q + j];
        sy += e.output[k * q + j];
      }
      d.input.push_back(su / static_cast<double>(q));
      d.output.push_back(sy / static_cast<double>(q));
    }
    try {
      SubspaceOptions so;
      so.block_rows = std::max<std::size_t>(10, 2 * static_cast<std::size_t>(order));
      const SubspaceModel m = n4sid(d, static_cast<std::size_t>(order), so);
      const Eigen::VectorXcd values = linalg::eigen(m.model.a).values;
      std::vector<std::complex<double>> poles;
      for (Eigen::Index k = 0; k < values.size(); ++k) {
        const std::complex<double> z = values(k);
        if (std::abs(z) == 0.0) continue;
        poles.push_back(std::log(z) / d.sample_time_s);  // s = ln z / T
      }
      out.push_back(poles);
    } catch (const std::exception&) {
      // A failed subspace step only removes seeds.
    }
  }
  return out;
}

}  // namespace

int process_order(const lti::ProcessStructure& s) {
  return (s.integrator ? 1 : 0) + s.pole_count;
}

std::vector<double> Layout::values(const double* theta) const {
  std::vector<double> v(fixed_value);
  for (std::size_t slot = 0; slot < free.size(); ++slot) {
    const auto p = static_cast<std::size_t>(free[slot]);
    v[p] = log_scale[p] ? std::exp(theta[slot]) : theta[slot];
  }
  return v;
}

std::vector<double> Layout::chain(const double* theta) const {
  std::vector<double> c(free.size(), 1.0);
  for (std::size_t slot = 0; slot < free.size(); ++slot) {
    const auto p = static_cast<std::size_t>(free[slot]);
    if (log_scale[p]) c[slot] = std::exp(theta[slot]);
  }
  return c;
}

std::vector<double> Layout::theta(std::span<const double> v) const {
  std::vector<double> t(free.size());
  for (std::size_t slot = 0; slot < free.size(); ++slot) {
    const auto p = static_cast<std::size_t>(free[slot]);
    t[slot] = log_scale[p] ? std::log(v[p]) : v[p];
  }
  return t;
}

bool Layout::is_fixed(int parameter) const {
  return parameter >= 0 && !std::isnan(fixed_value[static_cast<std::size_t>(parameter)]);
}

Layout make_layout(const lti::ProcessStructure& s, const ProcessFitOptions& options, double max_delay_s) {
  Layout l;
  l.structure = s;
  for (auto n : s.parameter_names()) l.names.emplace_back(n);
  const std::size_t count = l.names.size();
  l.fixed_value.assign(count, kNaN);
  l.log_scale.assign(count, false);
  l.lower.assign(count, -std::numeric_limits<double>::infinity());
  l.upper.assign(count, std::numeric_limits<double>::infinity());
  l.initial.assign(count, std::nullopt);
  for (const auto& [name, setting] : options.parameters) {
    bool known = false;
    for (std::size_t i = 0; i < count; ++i) {
      if (!iequals(name, l.names[i])) continue;
      known = true;
      if (setting.fixed) l.fixed_value[i] = *setting.fixed;
      l.initial[i] = setting.initial;
      l.lower[i] = setting.lower;
      l.upper[i] = setting.upper;
    }
    if (!known) {
      std::string list;
      for (const auto& n : l.names) list += (list.empty() ? "" : ", ") + n;
      throw InvalidArgument("parameter \"" + name + "\" is not part of process model " + s.code() +
                            "; its parameters are " + list + ".");
    }
  }
  for (std::size_t i = 0; i < count; ++i) {
    const std::string& name = l.names[i];
    const int k = static_cast<int>(i);
    if (name == "Kp") l.kp = k;
    if (name == "Tz") l.tz = k;
    if (name == "Td") l.td = k;
    if (name == "Zeta") l.zeta = k;
    const std::string label = name + " (" + s.code() + ")";
    if (!(l.lower[i] < l.upper[i])) {
      throw InvalidArgument("bounds of " + label + ": lower " + std::to_string(l.lower[i]) + " must be below upper " +
                            std::to_string(l.upper[i]) + ".");
    }
    if (positive_parameter(name)) {
      if (name == "Zeta" && !std::isfinite(l.upper[i])) l.upper[i] = options.max_zeta;
      if (!std::isnan(l.fixed_value[i])) {
        require_positive(label + " fixed value", l.fixed_value[i],
                         "Fixed time constants and Zeta must be > 0; use a structure without this factor to drop it.");
      } else {
        l.log_scale[i] = true;
      }
    } else if (name == "Td") {
      l.lower[i] = std::max(l.lower[i], 0.0);
      l.upper[i] = std::min(l.upper[i], max_delay_s);
      if (!std::isnan(l.fixed_value[i])) require_non_negative(label + " fixed value", l.fixed_value[i], "Td is a dead time in seconds.");
    }
    if (!std::isnan(l.fixed_value[i])) {
      require_finite(label + " fixed value", l.fixed_value[i]);
    } else {
      l.free.push_back(k);
      if (l.initial[i] && !(*l.initial[i] >= l.lower[i] && *l.initial[i] <= l.upper[i])) {
        throw_invalid(label + " initial value", *l.initial[i],
                      "[" + std::to_string(l.lower[i]) + ", " + std::to_string(l.upper[i]) + "] (its bounds)");
      }
      if (l.log_scale[i] && l.initial[i]) require_positive(label + " initial value", *l.initial[i]);
    }
  }
  return l;
}

std::vector<double> canonical(const Layout& l, std::vector<double> v) {
  auto index = [&](const char* name) {
    for (std::size_t i = 0; i < l.names.size(); ++i)
      if (l.names[i] == name) return static_cast<int>(i);
    return -1;
  };
  auto free_with_same_bounds = [&](const std::vector<int>& idx) {
    for (int i : idx) {
      const auto u = static_cast<std::size_t>(i), f = static_cast<std::size_t>(idx.front());
      if (i < 0 || l.is_fixed(i) || l.lower[u] != l.lower[f] || l.upper[u] != l.upper[f]) return false;
    }
    return true;
  };
  const lti::ProcessStructure& s = l.structure;
  if (!s.underdamped && s.pole_count >= 2) {  // real poles are exchangeable: Tp1 ≥ Tp2 ≥ Tp3
    std::vector<int> idx;
    for (const char* name : {"Tp1", "Tp2", "Tp3"})
      if (index(name) >= 0) idx.push_back(index(name));
    if (free_with_same_bounds(idx)) {
      std::vector<double> tps;
      for (int i : idx) tps.push_back(v[static_cast<std::size_t>(i)]);
      std::sort(tps.rbegin(), tps.rend());
      for (std::size_t k = 0; k < idx.size(); ++k) v[static_cast<std::size_t>(idx[k])] = tps[k];
    }
  }
  const int tw = index("Tw"), zeta = index("Zeta"), tp3 = index("Tp3");
  if (s.underdamped && tp3 >= 0 && !l.is_fixed(tw) && !l.is_fixed(zeta) && !l.is_fixed(tp3)) {
    const auto iw = static_cast<std::size_t>(tw), iz = static_cast<std::size_t>(zeta), ip = static_cast<std::size_t>(tp3);
    const double z = v[iz];
    if (z > 1.0) {
      // ζ > 1: three real poles (rates) that the pair and Tp3 can share in three ways; keep the
      // pair of the two closest poles (smallest ζ), continuous with the underdamped case.
      const double r = std::sqrt(z * z - 1.0);
      const double p[3] = {(z - r) / v[iw], (z + r) / v[iw], 1.0 / v[ip]};
      auto pair_zeta = [](double a, double b) { return (a + b) / (2.0 * std::sqrt(a * b)); };  // (1+2ζTw s+Tw²s²)
      int best = 2;  // index of the pole left for Tp3
      double best_z = z;
      for (int k = 0; k < 2; ++k) {
        const double zk = pair_zeta(p[1 - k], p[2]);
        if (zk < best_z - 1e-12) {
          best_z = zk;
          best = k;
        }
      }
      if (best != 2) {
        const double a = p[best == 0 ? 1 : 0], b = p[2];
        const double nw = 1.0 / std::sqrt(a * b), np = 1.0 / p[best];
        if (best_z >= l.lower[iz] && best_z <= l.upper[iz] && nw >= l.lower[iw] && nw <= l.upper[iw] &&
            np >= l.lower[ip] && np <= l.upper[ip]) {
          v[iw] = nw;
          v[iz] = best_z;
          v[ip] = np;
        }
      }
    }
  }
  return v;
}

double noise_level(std::span<const double> y) {
  // Robust white-noise σ: median absolute second difference (≈ σ√6 for a smooth signal + noise).
  if (y.size() < 3) return 0.0;
  std::vector<double> d2;
  d2.reserve(y.size() - 2);
  for (std::size_t k = 1; k + 1 < y.size(); ++k) d2.push_back(std::abs(y[k + 1] - 2.0 * y[k] + y[k - 1]));
  auto mid = d2.begin() + static_cast<std::ptrdiff_t>(d2.size() / 2);
  std::nth_element(d2.begin(), mid, d2.end());
  return 1.4826 * (*mid) / std::sqrt(6.0);
}

bool starts_at_rest(std::span<const double> y, bool relative_to_first) {
  if (y.size() < 3) return true;
  const auto [lo, hi] = std::minmax_element(y.begin(), y.end());
  const double range = *hi - *lo;
  if (!(range > 0.0)) return true;
  const double sigma = noise_level(y);
  const double ref = relative_to_first ? y[0] : 0.0;
  // At rest: the first sample at the rest level (0, or y[0] itself with an output offset).
  return std::abs(y[0] - ref) <= std::max(0.02 * range, 4.0 * sigma);
}

namespace {

// The candidate starting points of one structure, collected in the order they are made.
class Candidates {
 public:
  Candidates(const Layout& l, std::vector<double> delays) : l_(l), delays_(std::move(delays)) {}

  // One configuration: the scale τ (Tw or Tp1), ζ and real time constants, at every delay guess.
  void add(double tw, double zeta, const std::vector<double>& tps) {
    if (!(tw > 0.0) || !std::isfinite(tw)) return;
    for (double td : delays_) {
      std::vector<double> v = values(tw, zeta, tps, td);
      if (!within_layout(v)) return;
      out_.push_back(std::move(v));
    }
  }

  // Shapes around a time scale τ.
  void shapes(double tau, const std::vector<double>& zetas) {
    const lti::ProcessStructure& s = l_.structure;
    if (s.underdamped) {
      for (double z : zetas) {
        if (s.pole_count == 3) {
          for (double r : {0.3, 1.0, 3.0}) add(tau, z, {r * tau});
        } else {
          add(tau, z, {});
        }
      }
    } else if (s.pole_count == 1) {
      add(tau, 1.0, {tau});
    } else if (s.pole_count == 2) {
      add(tau, 1.0, {tau, tau});
      add(tau, 1.0, {tau, 0.2 * tau});
    } else if (s.pole_count == 3) {
      add(tau, 1.0, {tau, tau, tau});
      add(tau, 1.0, {tau, 0.3 * tau, 0.3 * tau});
      add(tau, 1.0, {tau, 0.3 * tau, 0.05 * tau});
    }
  }

  std::vector<std::vector<double>> take() { return std::move(out_); }

 private:
  std::vector<double> values(double tw, double zeta, const std::vector<double>& tps, double td) const {
    const bool underdamped = l_.structure.underdamped;
    std::vector<double> v(l_.names.size(), 0.0);
    for (std::size_t i = 0; i < v.size(); ++i) {
      const std::string& name = l_.names[i];
      if (name == "Kp") v[i] = 1.0;
      if (name == "Tw") v[i] = tw;
      if (name == "Zeta") v[i] = std::clamp(zeta, 0.02, 2.5);
      if (name == "Td") v[i] = td;
      if (name == "Tp1") v[i] = tps.size() > 0 ? tps[0] : tw;
      if (name == "Tp2") v[i] = tps.size() > 1 ? tps[1] : tw;
      if (name == "Tp3") v[i] = underdamped ? (tps.empty() ? tw : tps[0]) : (tps.size() > 2 ? tps[2] : tw);
    }
    return v;
  }

  // Fixed values and bounds applied; false when a log-scaled parameter is not positive.
  bool within_layout(std::vector<double>& v) const {
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (l_.is_fixed(static_cast<int>(i))) v[i] = l_.fixed_value[i];
      else if (l_.log_scale[i]) v[i] = std::clamp(v[i], std::max(l_.lower[i], 1e-300), l_.upper[i]);
      if (l_.log_scale[i] && !(v[i] > 0.0)) return false;
    }
    return true;
  }

  const Layout& l_;
  std::vector<double> delays_;
  std::vector<std::vector<double>> out_;
};

// Delay guesses: none, or half the step's onset (a fixed Td: its value).
std::vector<double> delay_guesses(const Layout& l, const std::optional<StepSeed>& step) {
  std::vector<double> delays{0.0};
  if (l.td >= 0) {
    if (l.is_fixed(l.td)) {
      delays = {l.fixed_value[static_cast<std::size_t>(l.td)]};
    } else if (step && step->onset_s > 0.0) {
      delays.push_back(std::min(0.5 * step->onset_s, l.upper[static_cast<std::size_t>(l.td)]));
    }
  }
  return delays;
}

// (a) the step response: its overshoot's ωn and ζ, and its 63 % time.
void add_step_candidates(Candidates& c, const StepSeed& step, bool underdamped) {
  if (std::isfinite(step.wn_rad_s)) {
    const double tw = 1.0 / step.wn_rad_s;
    c.shapes(tw, {step.zeta, 0.5 * step.zeta, std::min(1.0, 2.0 * step.zeta)});
  }
  if (std::isfinite(step.t63_s)) c.shapes(underdamped ? 0.5 * step.t63_s : step.t63_s, {0.5, 0.9});
}

// (b) one subspace model's stable poles, slowest first, as the structure's time constants.
void add_pole_candidates(Candidates& c, const lti::ProcessStructure& s, std::vector<std::complex<double>> poles) {
  std::erase_if(poles, [](const std::complex<double>& p) { return !(p.real() < 0.0); });
  std::sort(poles.begin(), poles.end(), [](auto a, auto b) { return std::abs(a) < std::abs(b); });
  if (poles.empty()) return;
  std::vector<double> real_tc;
  std::complex<double> pair{0.0, 0.0};
  bool have_pair = false;
  for (const auto& p : poles) {
    if (std::abs(p.imag()) > 1e-9 * std::abs(p)) {
      if (!have_pair && p.imag() > 0.0) {
        pair = p;
        have_pair = true;
      }
    } else {
      real_tc.push_back(-1.0 / p.real());
    }
  }
  if (s.underdamped) {
    if (have_pair) {
      const double wn = std::abs(pair);
      c.add(1.0 / wn, -pair.real() / wn, real_tc.empty() ? std::vector<double>{} : std::vector<double>{real_tc[0]});
    } else if (real_tc.size() >= 2) {  // two real poles → Tw = √(τ1τ2), ζ = (τ1 + τ2)/(2√(τ1τ2))
      const double tw = std::sqrt(real_tc[0] * real_tc[1]);
      c.add(tw, (real_tc[0] + real_tc[1]) / (2.0 * tw),
            real_tc.size() > 2 ? std::vector<double>{real_tc[2]} : std::vector<double>{});
    }
    return;
  }
  std::vector<double> tcs = real_tc;
  if (have_pair) {
    tcs.push_back(1.0 / std::abs(pair));
    tcs.push_back(1.0 / std::abs(pair));
  }
  std::sort(tcs.rbegin(), tcs.rend());
  if (!tcs.empty()) c.add(tcs[0], 1.0, tcs);
}

// (c) a log-spaced grid of time scales between 2T and half the shortest record.
void add_grid_candidates(Candidates& c, const lti::ProcessStructure& s, double t_min, double d_min) {
  const double lo = 2.0 * t_min, hi = std::max(0.5 * d_min, 4.0 * lo);
  const int points = 10;
  for (int i = 0; i < points; ++i) {
    const double tau = lo * std::pow(hi / lo, static_cast<double>(i) / (points - 1));
    if (s.pole_count == 3) {
      c.shapes(tau, {0.2, 0.6});
    } else {
      c.shapes(tau, {0.15, 0.4, 0.8});
    }
  }
}

}  // namespace

std::vector<std::vector<double>> candidate_values(const Layout& l, std::span<const Experiment> experiments) {
  const lti::ProcessStructure& s = l.structure;
  double t_min = std::numeric_limits<double>::infinity(), d_min = std::numeric_limits<double>::infinity();
  for (const auto& e : experiments) {
    t_min = std::min(t_min, e.sample_time_s);
    d_min = std::min(d_min, e.duration_s());
  }
  std::optional<StepSeed> step;
  for (const auto& e : experiments) {
    step = analyse_step(e);
    if (step) break;
  }
  Candidates c(l, delay_guesses(l, step));
  if (s.pole_count == 0) {
    c.add(1.0, 1.0, {});
    return c.take();
  }
  if (step) add_step_candidates(c, *step, s.underdamped);
  const int order = process_order(s);
  for (const auto& e : experiments) {
    for (auto& poles : subspace_poles(e, order)) add_pole_candidates(c, s, std::move(poles));
  }
  add_grid_candidates(c, s, t_min, d_min);
  return c.take();
}

}  // namespace clearshape::ident::detail
