// Specified-insensitivity (SI) shaper (Singhose, Seering & Singer 1996; formulation as in
// Vaughan's si_shaping.py): the shortest positive shaper with V(ω, ζ) <= Vtol over a band.
//
//   minimise t_N  over A_i in [0, 1], increments t_{i+1} − t_i >= 0, t_1 = 0,
//   subject to ΣA = 1 and V(ω_k, ζ)² <= Vtol² at sampled band frequencies ω_k,
//
// solved with NLopt's SLSQP (analytic gradients). Frequencies are scaled by the band's geometric
// centre ωc and times by 1/ωc, so the band is [1/√R, √R] with R = ω_high/ω_low.
//
// Seed and continuation (deterministic): the seed is the closed-form shaper (ZV, EI, EI2, EI3,
// else ZVD/ZVDD/ZVDDD) of the shortest duration whose own V <= Vtol band is at least as wide
// (ratio R_s >= R), else the widest one, placed so that its band is centred on the requested
// one. The band ratio is then moved from R_s to R in steps of at most 5 % (in log), re-solving
// from the previous optimum; when a step is infeasible the largest impulse is split in two
// (at most twice per step; up to 40 impulses, or the count requested) and the step retried,
// else the step is halved. A step whose optimum is over 25 % longer than the previous one counts
// as failed (SLSQP left the branch). The constraints use Vtol·(1 − 1e-4). Each solve starts with `constraint_points` evenly spaced frequencies; every local maximum of V
// on the band (a 40× denser grid, refined by golden-section search) above Vtol is then added and
// the problem solved again, so the result meets V <= Vtol·(1 + 1e-6) everywhere on the band.
#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlopt.h>

#include "clearshape/core/error.hpp"
#include "clearshape/shaping/design.hpp"
#include "clearshape/shaping/residual.hpp"
#include "design_detail.hpp"

namespace clearshape::shaping {

namespace {

constexpr int kMaxImpulses = 40;

struct Problem {
  int n = 0;                   // impulses
  double zeta = 0.0;
  double vtol = 0.05;
  std::vector<double> rho;     // constraint frequencies / ωc
};

void unpack(const double* x, int n, std::vector<double>& a, std::vector<double>& t) {
  a.assign(x, x + n);
  t.assign(static_cast<std::size_t>(n), 0.0);
  for (int i = 1; i < n; ++i) t[static_cast<std::size_t>(i)] = t[static_cast<std::size_t>(i - 1)] + x[n + i - 1];
}

double objective(unsigned dim, const double* x, double* grad, void* data) {
  const int n = static_cast<const Problem*>(data)->n;
  double sum = 0.0;
  for (unsigned i = 0; i < dim; ++i) {
    const bool is_increment = static_cast<int>(i) >= n;
    if (is_increment) sum += x[i];
    if (grad != nullptr) grad[i] = is_increment ? 1.0 : 0.0;
  }
  return sum;  // t_N = Σ increments
}

double amplitude_sum(unsigned dim, const double* x, double* grad, void* data) {
  const int n = static_cast<const Problem*>(data)->n;
  double sum = -1.0;
  for (unsigned i = 0; i < dim; ++i) {
    const bool is_amplitude = static_cast<int>(i) < n;
    if (is_amplitude) sum += x[i];
    if (grad != nullptr) grad[i] = is_amplitude ? 1.0 : 0.0;
  }
  return sum;  // ΣA − 1 = 0 (Eq. 2.21)
}

// c_k = |W(ρ_k)|²/Vtol² − 1 <= 0, with the gradient of |W|² = 2 Re(W̄ ∂W) (Eq. 2.19).
void band_constraints(unsigned m, double* result, unsigned dim, const double* x, double* grad, void* data) {
  const Problem& p = *static_cast<const Problem*>(data);
  const int n = p.n;
  std::vector<double> a;
  std::vector<double> t;
  unpack(x, n, a, t);
  const double root = std::sqrt(1.0 - p.zeta * p.zeta);
  const std::complex<double> s(p.zeta, root);
  double amp_sum = 0.0;
  for (double v : a) amp_sum += v;
  // V = |W|/ΣA (Eq. 2.19 normalised): c = |W|²/(ΣA·Vtol)² − 1.
  const double scale = 1.0 / (p.vtol * p.vtol * amp_sum * amp_sum);
  std::vector<std::complex<double>> unit(static_cast<std::size_t>(n));
  std::vector<double> d_time(static_cast<std::size_t>(n));
  for (unsigned k = 0; k < m; ++k) {
    const double rho = p.rho[k];
    std::complex<double> w{0.0, 0.0};
    for (int i = 0; i < n; ++i) {
      const auto u = static_cast<std::size_t>(i);
      unit[u] = std::exp(-p.zeta * rho * (t.back() - t[u])) *
                std::complex<double>(std::cos(root * rho * t[u]), std::sin(root * rho * t[u]));
      w += a[u] * unit[u];
    }
    result[k] = std::norm(w) * scale - 1.0;
    if (grad == nullptr) continue;
    double* g = grad + static_cast<std::size_t>(k) * dim;
    const std::complex<double> wc = std::conj(w);
    for (int i = 0; i < n; ++i) {
      const auto u = static_cast<std::size_t>(i);
      g[u] = (2.0 * (wc * unit[u]).real() - 2.0 * std::norm(w) / amp_sum) * scale;
      std::complex<double> dw = rho * s * a[u] * unit[u];
      if (i == n - 1) dw -= p.zeta * rho * w;
      d_time[u] = 2.0 * (wc * dw).real() * scale;
    }
    // t_i = Σ_{j<i} d_j: ∂/∂d_j = Σ_{i>j} ∂/∂t_i.
    double tail = 0.0;
    for (int j = n - 2; j >= 0; --j) {
      tail += d_time[static_cast<std::size_t>(j + 1)];
      g[static_cast<std::size_t>(n + j)] = tail;
    }
  }
}

// Local maxima of V over [lo, hi] (dense grid, golden-section refined) above `threshold`.
std::vector<double> band_peaks(const std::vector<double>& a, const std::vector<double>& t, double zeta,
                               double lo, double hi, std::size_t grid, double threshold, double& max_v) {
  auto v = [&](double rho) { return std::abs(detail::residual_phasor(a, t, rho, zeta)); };
  std::vector<double> values(grid);
  const double h = (hi - lo) / static_cast<double>(grid - 1);
  for (std::size_t i = 0; i < grid; ++i) values[i] = v(lo + static_cast<double>(i) * h);
  std::vector<double> peaks;
  max_v = 0.0;
  for (std::size_t i = 0; i < grid; ++i) {
    const bool left = i == 0 || values[i] >= values[i - 1];
    const bool right = i + 1 == grid || values[i] >= values[i + 1];
    if (!(left && right)) continue;
    double x = lo + static_cast<double>(i) * h;
    double vx = values[i];
    if (i > 0 && i + 1 < grid) {  // golden-section search on the bracketing cell pair
      const double g = (std::sqrt(5.0) - 1.0) / 2.0;
      double xa = x - h;
      double xb = x + h;
      for (int it = 0; it < 60; ++it) {
        const double x1 = xb - g * (xb - xa);
        const double x2 = xa + g * (xb - xa);
        if (v(x1) >= v(x2)) xb = x2; else xa = x1;
      }
      x = 0.5 * (xa + xb);
      vx = std::max(vx, v(x));
    }
    max_v = std::max(max_v, vx);
    if (vx > threshold) peaks.push_back(x);
  }
  return peaks;
}

struct NloptDeleter {
  void operator()(nlopt_opt o) const noexcept { nlopt_destroy(o); }
};

void run_slsqp(Problem& p, std::vector<double>& x, double time_upper) {
  const int n = p.n;
  const auto dim = static_cast<unsigned>(2 * n - 1);
  std::unique_ptr<nlopt_opt_s, NloptDeleter> opt(nlopt_create(NLOPT_LD_SLSQP, dim));
  if (!opt) throw RuntimeError("si: NLopt could not create the SLSQP optimiser");
  std::vector<double> lower(dim, 0.0);
  std::vector<double> upper(dim, 1.0);
  for (unsigned i = static_cast<unsigned>(n); i < dim; ++i) upper[i] = time_upper;
  nlopt_set_lower_bounds(opt.get(), lower.data());
  nlopt_set_upper_bounds(opt.get(), upper.data());
  nlopt_set_min_objective(opt.get(), objective, &p);
  nlopt_add_equality_constraint(opt.get(), amplitude_sum, &p, 1e-13);
  const std::vector<double> tolerances(p.rho.size(), 1e-10);
  nlopt_add_inequality_mconstraint(opt.get(), static_cast<unsigned>(p.rho.size()), band_constraints, &p,
                                   tolerances.data());
  nlopt_set_ftol_rel(opt.get(), 1e-13);
  nlopt_set_xtol_rel(opt.get(), 1e-11);
  nlopt_set_maxeval(opt.get(), 4000);
  double value = 0.0;
  // Any return code leaves the last iterate in x; feasibility is checked by the caller.
  nlopt_optimize(opt.get(), x.data(), &value);
}

// A candidate solution: x = [A_1 … A_n | increments t_{i+1} − t_i] (times · ωc).
struct State {
  int n = 0;
  std::vector<double> x;
};

State state_from(const Shaper& shaper) {
  State st;
  st.n = static_cast<int>(shaper.size());
  st.x.assign(static_cast<std::size_t>(2 * st.n - 1), 0.0);
  const auto q = shaper.impulses();
  for (std::size_t i = 0; i < q.size(); ++i) {
    st.x[i] = q[i].amplitude;
    if (i > 0) st.x[static_cast<std::size_t>(st.n) + i - 1] = q[i].time_s - q[i - 1].time_s;
  }
  return st;
}

// Splits the largest impulse into two halves 0.02 rad (·1/ωc) apart, centred on it when possible:
// V changes only to second order, and the optimiser gets one more impulse to move.
State split_largest(const State& st) {
  std::vector<double> a;
  std::vector<double> t;
  unpack(st.x.data(), st.n, a, t);
  const auto k = static_cast<std::size_t>(std::max_element(a.begin(), a.end()) - a.begin());
  constexpr double kHalfGap = 0.01;
  std::vector<double> a2;
  std::vector<double> t2;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (i != k) {
      a2.push_back(a[i]);
      t2.push_back(t[i]);
      continue;
    }
    const double lo = std::max(t[i] - kHalfGap, i > 0 ? 0.5 * (t[i - 1] + t[i]) : 0.0);
    const double hi = std::min(lo + 2.0 * kHalfGap, i + 1 < a.size() ? 0.5 * (t[i] + t[i + 1]) : lo + 2.0 * kHalfGap);
    a2.insert(a2.end(), {0.5 * a[i], 0.5 * a[i]});
    t2.insert(t2.end(), {lo, hi});
  }
  State out;
  out.n = st.n + 1;
  out.x.assign(static_cast<std::size_t>(2 * out.n - 1), 0.0);
  for (int i = 0; i < out.n; ++i) {
    const auto u = static_cast<std::size_t>(i);
    out.x[u] = a2[u];
    if (i > 0) out.x[static_cast<std::size_t>(out.n + i - 1)] = t2[u] - t2[u - 1];
  }
  return out;
}

// Solves the SI problem on [1/√R, √R] from `st` (in place) with constraint refinement; returns
// the maximum of V on the band.
double solve_band(State& st, double zeta, double vtol, double ratio, std::size_t points) {
  const double lo = 1.0 / std::sqrt(ratio);
  const double hi = std::sqrt(ratio);
  Problem p;
  p.n = st.n;
  p.zeta = zeta;
  p.vtol = vtol * (1.0 - 1e-4);  // a small margin absorbs excursions between the samples
  for (std::size_t k = 0; k < points; ++k) {
    p.rho.push_back(lo + (hi - lo) * static_cast<double>(k) / static_cast<double>(points - 1));
  }
  std::vector<double> a;
  std::vector<double> t;
  unpack(st.x.data(), st.n, a, t);
  const double time_upper = 4.0 * std::max(t.back(), 2.0 * std::numbers::pi);
  const std::size_t grid = std::max<std::size_t>(2001, 40 * points);
  double max_v = 0.0;
  for (int round = 0; round < 10; ++round) {
    run_slsqp(p, st.x, time_upper);
    unpack(st.x.data(), st.n, a, t);
    double sum = 0.0;
    for (double& v : a) sum += (v = std::max(v, 0.0));
    for (double& v : a) v /= sum;
    // SLSQP could not satisfy its own constraint set: infeasible from here.
    double worst = 0.0;
    for (double rho : p.rho) worst = std::max(worst, std::abs(detail::residual_phasor(a, t, rho, zeta)));
    const std::vector<double> peaks = band_peaks(a, t, zeta, lo, hi, grid, vtol * (1.0 + 1e-9), max_v);
    if (peaks.empty() || worst > vtol * (1.0 + 1e-6)) break;
    p.rho.insert(p.rho.end(), peaks.begin(), peaks.end());
  }
  // Store the normalised, clipped amplitudes back.
  for (int i = 0; i < st.n; ++i) st.x[static_cast<std::size_t>(i)] = a[static_cast<std::size_t>(i)];
  return max_v;
}

double duration_of(const State& st) {
  double sum = 0.0;
  for (std::size_t i = static_cast<std::size_t>(st.n); i < st.x.size(); ++i) sum += st.x[i];
  return sum;
}

double zv_limit_ratio(double zeta, double vtol) {
  const Mode unit{1.0, zeta};
  const InsensitivityBand band = insensitivity(design_zv_derivatives(unit, kMaxImpulses - 2), unit, vtol);
  return band.ratio_high / band.ratio_low;
}

struct Seed {
  Shaper shaper;   // designed so that its band is centred on ρ = 1
  double ratio;    // R_s: its own band ratio at vtol
};

std::optional<Seed> make_seed(Method method, double zeta, double vtol) {
  const Mode unit{1.0, zeta};
  std::optional<Shaper> shaper;
  try {
    DesignRequest request;
    request.method = method;
    request.mode = unit;
    request.vtol = vtol;
    shaper = design(request);
  } catch (const InvalidArgument&) {
    return std::nullopt;  // EI family beyond its damping range
  }
  const InsensitivityBand band = insensitivity(*shaper, unit, vtol);
  if (!(band.width() > 0.0)) return std::nullopt;
  const double rho_s = 1.0 / std::sqrt(band.ratio_low * band.ratio_high);
  std::vector<Impulse> impulses;
  for (const Impulse& q : shaper->impulses()) impulses.push_back({q.time_s / rho_s, q.amplitude});
  return Seed{Shaper(shaper->method(), std::move(impulses), Shaper::Normalize::yes),
              band.ratio_high / band.ratio_low};
}

// The shortest candidate covering the ratio, else the widest (with at most `max_impulses`).
Seed choose_seed(double zeta, double vtol, double ratio, int max_impulses) {
  std::vector<Seed> candidates;
  for (Method m : {Method::zv, Method::ei, Method::ei2, Method::ei3}) {
    if (auto s = make_seed(m, zeta, vtol)) candidates.push_back(std::move(*s));
  }
  if (candidates.size() < 4) {  // the EI family does not exist at this damping: ZV family
    for (Method m : {Method::zvd, Method::zvdd, Method::zvddd}) {
      if (auto s = make_seed(m, zeta, vtol)) candidates.push_back(std::move(*s));
    }
  }
  std::erase_if(candidates, [&](const Seed& s) { return static_cast<int>(s.shaper.size()) > max_impulses; });
  if (candidates.empty()) {
    throw InvalidArgument(fmt::format("si: impulses = {} is too few for a seed; allowed: 0 (automatic) or 2 … {}",
                                      max_impulses, kMaxImpulses));
  }
  const Seed* best = nullptr;
  for (const Seed& s : candidates) {
    if (s.ratio >= ratio && (best == nullptr || s.shaper.duration_s() < best->shaper.duration_s())) best = &s;
  }
  if (best == nullptr) {
    for (const Seed& s : candidates) {
      if (best == nullptr || s.ratio > best->ratio) best = &s;
    }
  }
  return *best;
}

void validate_si(const Mode& mode, const SiOptions& options) {
  detail::validate_mode(mode, "si");
  detail::validate_vtol(options.vtol, "si");
  require_positive("si: frequency_low_rad_s", options.frequency_low_rad_s,
                   "give the band over which V <= vtol must hold");
  if (!(std::isfinite(options.frequency_high_rad_s) && options.frequency_high_rad_s > options.frequency_low_rad_s)) {
    throw_invalid("si: frequency_high_rad_s", options.frequency_high_rad_s,
                  fmt::format("finite and > frequency_low_rad_s = {}", options.frequency_low_rad_s));
  }
  if (options.impulses != 0 && (options.impulses < 2 || options.impulses > kMaxImpulses)) {
    throw_invalid("si: impulses", options.impulses, fmt::format("0 (automatic) or 2 … {}", kMaxImpulses));
  }
  if (options.constraint_points < 2 || options.constraint_points > 10000) {
    throw_invalid("si: constraint_points", options.constraint_points, "2 … 10000");
  }
}

// Practical limit (checked when the seed must be widened): the band of the ZV shaper with 38
// derivatives (40 impulses) at this vtol.
void check_band_limit(const Seed& seed, double ratio, double zeta, double vtol) {
  if (seed.ratio >= ratio) return;
  const double limit = zv_limit_ratio(zeta, vtol);
  if (ratio > limit) {
    throw InvalidArgument(fmt::format(
        "si: the band ratio high/low = {:.4g} is out of range; allowed: <= {:.4g} at vtol = {} and "
        "damping_ratio = {} (the band of a 40-impulse ZV-family shaper). The band is too wide: "
        "narrow it or raise vtol", ratio, limit, vtol, zeta));
  }
}

// The continuation's fixed data: the mode, the tolerance and the band to reach.
struct BandTarget {
  double zeta = 0.0, vtol = 0.0, ratio = 1.0;
  std::size_t points = 0;  ///< constraint points over the band
  int max_impulses = 0;
};

// Continuation in log R from the seed's band (log_r) to the target band; an impulse is split
// when a step fails, then the step halves.
State continue_to_band(State state, double log_r, const BandTarget& b) {
  const double log_target = std::log(b.ratio);
  double step = 0.05;
  double max_v = 0.0;
  bool done = false;
  int splits = 0;  // splits at the current step
  while (!done) {
    const double next = log_r < log_target ? std::min(log_target, log_r + step) : std::max(log_target, log_r - step);
    State trial = state;
    max_v = solve_band(trial, b.zeta, b.vtol, std::exp(next), b.points);
    // A feasible optimum far longer than the previous one means SLSQP left the branch.
    const bool kept_branch = duration_of(trial) <= 1.25 * duration_of(state) + 1e-9;
    if (max_v <= b.vtol * (1.0 + 1e-6) && kept_branch) {
      state = std::move(trial);
      log_r = next;
      done = next == log_target;
      step = std::min(0.05, 2.0 * step);
      splits = 0;
    } else if (state.n < b.max_impulses && splits < 2) {
      state = split_largest(state);
      ++splits;
    } else if ((step *= 0.5) < 1e-3) {
      throw RuntimeError(fmt::format(
          "si: no {}-impulse positive shaper was found with V <= {} over the band ratio {:.4g} "
          "(max V = {:.4g} at ratio {:.4g}); use more impulses (or impulses = 0 to choose "
          "automatically), a narrower band or a larger vtol",
          state.n, b.vtol, b.ratio, max_v, std::exp(next)));
    }
  }
  return state;
}

// The state's impulses in seconds (times are in units of 1/centre). Impulses that ended at the
// same time are merged and empty ones dropped (V is unchanged by both and by a common time
// shift, so the first kept impulse moves to t = 0).
std::vector<Impulse> impulses_of(const State& state, double centre_rad_s) {
  std::vector<double> a;
  std::vector<double> t;
  unpack(state.x.data(), state.n, a, t);
  std::vector<Impulse> impulses;
  const double merge_tol = 1e-9 * std::max(t.back(), 1.0);
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!impulses.empty() && t[i] - impulses.back().time_s <= merge_tol) {
      impulses.back().amplitude += a[i];
    } else {
      impulses.push_back({t[i], a[i]});
    }
  }
  std::erase_if(impulses, [](const Impulse& q) { return q.amplitude <= 1e-12; });
  const double shift = impulses.front().time_s;
  for (Impulse& q : impulses) q.time_s = (q.time_s - shift) / centre_rad_s;
  return impulses;
}

}  // namespace

Shaper design_si(const Mode& mode, const SiOptions& options) {
  validate_si(mode, options);
  BandTarget b;
  b.zeta = mode.damping_ratio;
  b.vtol = options.vtol;
  b.ratio = options.frequency_high_rad_s / options.frequency_low_rad_s;
  b.points = static_cast<std::size_t>(options.constraint_points);
  b.max_impulses = options.impulses > 0 ? options.impulses : kMaxImpulses;
  const double centre_rad_s = std::sqrt(options.frequency_low_rad_s * options.frequency_high_rad_s);

  const Seed seed = choose_seed(b.zeta, b.vtol, b.ratio, b.max_impulses);
  check_band_limit(seed, b.ratio, b.zeta, b.vtol);
  State state = state_from(seed.shaper);
  while (options.impulses > 0 && state.n < options.impulses) state = split_largest(state);
  state = continue_to_band(std::move(state), std::log(seed.ratio), b);
  return Shaper("si", impulses_of(state, centre_rad_s), Shaper::Normalize::yes);
}

}  // namespace clearshape::shaping
