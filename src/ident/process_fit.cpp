#include "clearshape/ident/process_fit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include <ceres/ceres.h>

#include "clearshape/core/error.hpp"
#include "clearshape/lti/simulate.hpp"
#include "clearshape/metrics/fit.hpp"
#include "covariance.hpp"
#include "process_detail.hpp"
#include "process_sampling.hpp"

namespace clearshape::ident {

namespace {

using detail::Layout;
using detail::Sampled;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Prepared {
  const Experiment* e = nullptr;
  double weight = 1.0;  // 1/√(N var y): each experiment weighs equally
  bool x0 = false, u0 = false, y0 = false;
  std::size_t nuisance(int n) const { return (x0 ? static_cast<std::size_t>(n) : 0) + (u0 ? 1 : 0) + (y0 ? 1 : 0); }
};

// The sampled model (and its derivatives) for the current parameters, shared by the residual
// blocks of all experiments with the same sample time (Ceres evaluates them one after another).
class ModelCache {
 public:
  ModelCache(lti::ProcessStructure s, lti::Hold hold) : structure_(s), hold_(hold) {}
  const Sampled& get(const std::vector<double>& values, double sample_time_s, bool derivatives) {
    for (auto& e : entries_) {
      if (e.sample_time_s != sample_time_s) continue;
      if (e.values != values || (derivatives && !e.derivatives)) {
        e.sampled = detail::sample(structure_, values, sample_time_s, hold_, derivatives);
        e.values = values;
        e.derivatives = derivatives;
      }
      return e.sampled;
    }
    entries_.push_back({sample_time_s, values, derivatives, detail::sample(structure_, values, sample_time_s, hold_, derivatives)});
    return entries_.back().sampled;
  }

 private:
  struct Entry {
    double sample_time_s;
    std::vector<double> values;
    bool derivatives;
    Sampled sampled;
  };
  lti::ProcessStructure structure_;
  lti::Hold hold_;
  std::vector<Entry> entries_;
};

// Nuisance vector layout: [x0 (n)] [u0] [y0].
struct Nuisance {
  std::vector<double> x0;
  double u0 = 0.0, y0 = 0.0;
};
Nuisance split(const Prepared& p, int n, const double* v) {
  Nuisance out;
  std::size_t i = 0;
  if (p.x0) {
    out.x0.assign(v, v + n);
    i += static_cast<std::size_t>(n);
  }
  if (p.u0) out.u0 = v[i++];
  if (p.y0) out.y0 = v[i++];
  return out;
}

// ŷ (and ∂ŷ/∂[free parameters, x0, u0, y0] when jacobian != nullptr) for one experiment.
bool simulate_experiment(const Sampled& m, const Prepared& p, const Nuisance& nu, std::span<const int> directions,
                         std::span<const double> scale, std::vector<double>& u_scratch, double* y, double* jacobian) {
  const Experiment& e = *p.e;
  u_scratch.resize(e.size());
  for (std::size_t k = 0; k < e.size(); ++k) u_scratch[k] = e.input[k] - nu.u0;
  detail::KernelInput in;
  in.model = &m;
  in.input = u_scratch;
  in.x0 = nu.x0;
  in.y0 = nu.y0;
  in.directions = directions;
  in.scale = scale;
  in.d_x0 = p.x0;
  in.d_u0 = p.u0;
  in.d_y0 = p.y0;
  return detail::simulate(in, y, jacobian);
}

class ExperimentCost final : public ceres::CostFunction {
 public:
  ExperimentCost(const Layout& layout, const Prepared& p, int order, ModelCache& cache)
      : layout_(layout), p_(p), order_(order), cache_(cache) {
    set_num_residuals(static_cast<int>(p.e->size()));
    if (!layout.free.empty()) mutable_parameter_block_sizes()->push_back(static_cast<int>(layout.free.size()));
    if (p.nuisance(order) > 0) mutable_parameter_block_sizes()->push_back(static_cast<int>(p.nuisance(order)));
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const std::size_t np = layout_.free.size();
    const std::size_t nn = p_.nuisance(order_);
    const double* theta = np > 0 ? parameters[0] : nullptr;
    const double* nuis = nn > 0 ? parameters[np > 0 ? 1 : 0] : nullptr;
    const std::vector<double> values = layout_.values(theta);
    const std::vector<double> chain = layout_.chain(theta);
    const bool want = jacobians != nullptr;
    const Sampled& m = cache_.get(values, p_.e->sample_time_s, want && np > 0);
    const Nuisance nu = split(p_, order_, nuis);
    const std::size_t n = p_.e->size();
    y_.resize(n);
    if (want) jac_.assign(n * (np + nn), 0.0);
    if (!simulate_experiment(m, p_, nu, layout_.free, chain, u_, y_.data(), want ? jac_.data() : nullptr)) return false;
    const double w = p_.weight;
    for (std::size_t k = 0; k < n; ++k) residuals[k] = w * (y_[k] - p_.e->output[k]);
    if (!want) return true;
    std::size_t block = 0;
    if (np > 0) {
      if (jacobians[block] != nullptr) {
        for (std::size_t k = 0; k < n; ++k)
          for (std::size_t i = 0; i < np; ++i) jacobians[block][k * np + i] = w * jac_[k * (np + nn) + i];
      }
      ++block;
    }
    if (nn > 0 && jacobians[block] != nullptr) {
      for (std::size_t k = 0; k < n; ++k)
        for (std::size_t i = 0; i < nn; ++i) jacobians[block][k * nn + i] = w * jac_[k * (np + nn) + np + i];
    }
    return true;
  }

 private:
  const Layout& layout_;
  const Prepared& p_;
  int order_;
  ModelCache& cache_;
  mutable std::vector<double> y_, jac_, u_;
};

struct Start {
  std::vector<double> values;
  std::vector<std::vector<double>> nuisance;  // per experiment
  double cost = 0.0;
};

// Ranking of a pole configuration: Kp, Kp·Tz, the initial-state basis and the offset enter the
// simulated output linearly, so they are solved by least squares (variable projection).
std::optional<Start> rank(const Layout& l, const std::vector<Prepared>& prep, std::vector<double> v, lti::Hold hold,
                          int n) {
  const bool has_z = l.structure.zero;
  const bool kp_fixed = l.is_fixed(l.kp);
  const bool tz_fixed = has_z && l.is_fixed(l.tz);
  const double kp_val = kp_fixed ? l.fixed_value[static_cast<std::size_t>(l.kp)] : 1.0;
  const double tz_val = tz_fixed ? l.fixed_value[static_cast<std::size_t>(l.tz)] : 0.0;
  enum class Mode { kp_tz, kp, tz, none } mode;
  if (!has_z) mode = kp_fixed ? Mode::none : Mode::kp;
  else if (!kp_fixed && !tz_fixed) mode = Mode::kp_tz;
  else if (!kp_fixed) mode = Mode::kp;
  else if (!tz_fixed) mode = Mode::tz;
  else mode = Mode::none;
  const Eigen::Index m_shared = mode == Mode::kp_tz ? 2 : (mode == Mode::none ? 0 : 1);

  struct Local {
    Eigen::MatrixXd a;
    Eigen::VectorXd b;
    Eigen::Index offset = 0;  // of the experiment's columns in the global vector
    Sampled s0;
    Eigen::RowVectorXd c1;
  };
  std::vector<Local> locals(prep.size());
  Eigen::Index m_total = m_shared;
  std::vector<double> v0 = v, v1 = v;
  v0[static_cast<std::size_t>(l.kp)] = 1.0;
  if (has_z) v0[static_cast<std::size_t>(l.tz)] = 0.0;
  v1[static_cast<std::size_t>(l.kp)] = 1.0;
  if (has_z) v1[static_cast<std::size_t>(l.tz)] = 1.0;
  for (std::size_t e = 0; e < prep.size(); ++e) {
    const Prepared& p = prep[e];
    const std::size_t count = p.e->size();
    const auto rows = static_cast<Eigen::Index>(count);
    Local& loc = locals[e];
    loc.s0 = detail::sample(l.structure, v0, p.e->sample_time_s, hold, false);
    std::vector<double> g0(count), g1(count, 0.0), basis(p.x0 ? count * static_cast<std::size_t>(n) : 0);
    Prepared only_x0 = p;
    only_x0.u0 = false;
    only_x0.y0 = false;
    std::vector<double> scratch;
    if (!simulate_experiment(loc.s0, only_x0, Nuisance{}, {}, {}, scratch, g0.data(), p.x0 ? basis.data() : nullptr)) {
      return std::nullopt;
    }
    if (has_z) {
      const Sampled s1 = detail::sample(l.structure, v1, p.e->sample_time_s, hold, false);
      Sampled diff = loc.s0;
      diff.c = s1.c - loc.s0.c;
      diff.h = s1.h - loc.s0.h;
      loc.c1 = diff.c;
      Prepared plain = p;
      plain.x0 = plain.u0 = plain.y0 = false;
      if (!simulate_experiment(diff, plain, Nuisance{}, {}, {}, scratch, g1.data(), nullptr)) return std::nullopt;
    } else {
      loc.c1 = Eigen::RowVectorXd::Zero(loc.s0.n);
    }
    const Eigen::Index m_e = (p.x0 ? n : 0) + (p.y0 ? 1 : 0);
    loc.a.resize(rows, m_shared + m_e);
    loc.b.resize(rows);
    loc.offset = m_total;
    m_total += m_e;
    for (std::size_t k = 0; k < count; ++k) {
      const auto r = static_cast<Eigen::Index>(k);
      double target = p.e->output[k];
      switch (mode) {
        case Mode::kp_tz:
          loc.a(r, 0) = g0[k];
          loc.a(r, 1) = g1[k];
          break;
        case Mode::kp: loc.a(r, 0) = g0[k] + tz_val * g1[k]; break;
        case Mode::tz:
          target -= kp_val * g0[k];
          loc.a(r, 0) = kp_val * g1[k];
          break;
        case Mode::none: target -= kp_val * (g0[k] + tz_val * g1[k]); break;
      }
      Eigen::Index c = m_shared;
      if (p.x0)
        for (int i = 0; i < n; ++i) loc.a(r, c++) = basis[k * static_cast<std::size_t>(n) + static_cast<std::size_t>(i)];
      if (p.y0) loc.a(r, c++) = 1.0;
      loc.b(r) = target;
    }
    loc.a *= p.weight;
    loc.b *= p.weight;
  }
  // Normal equations over the shared and per-experiment columns (Jacobi-scaled, tiny ridge).
  Eigen::VectorXd beta = Eigen::VectorXd::Zero(m_total);
  if (m_total > 0) {
    Eigen::MatrixXd g = Eigen::MatrixXd::Zero(m_total, m_total);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(m_total);
    for (const Local& loc : locals) {
      const Eigen::Index me = loc.a.cols() - m_shared;
      const Eigen::MatrixXd ata = loc.a.transpose() * loc.a;
      const Eigen::VectorXd atb = loc.a.transpose() * loc.b;
      g.topLeftCorner(m_shared, m_shared) += ata.topLeftCorner(m_shared, m_shared);
      g.block(0, loc.offset, m_shared, me) += ata.topRightCorner(m_shared, me);
      g.block(loc.offset, 0, me, m_shared) += ata.bottomLeftCorner(me, m_shared);
      g.block(loc.offset, loc.offset, me, me) += ata.bottomRightCorner(me, me);
      rhs.head(m_shared) += atb.head(m_shared);
      rhs.segment(loc.offset, me) += atb.tail(me);
    }
    Eigen::VectorXd d = g.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
    Eigen::MatrixXd gs = d.asDiagonal() * g * d.asDiagonal();
    gs.diagonal().array() += 1e-12;
    beta = d.asDiagonal() * gs.ldlt().solve(d.asDiagonal() * rhs);
    if (!beta.allFinite()) return std::nullopt;
  }
  Start start;
  double kp = kp_val, tz = tz_val;
  switch (mode) {
    case Mode::kp_tz:
      kp = beta(0);
      tz = std::abs(kp) > 0.0 ? beta(1) / kp : 0.0;
      break;
    case Mode::kp: kp = beta(0); break;
    case Mode::tz: tz = beta(0); break;
    case Mode::none: break;
  }
  if (!std::isfinite(kp) || !std::isfinite(tz) || kp == 0.0) return std::nullopt;
  kp = std::clamp(kp, l.lower[static_cast<std::size_t>(l.kp)], l.upper[static_cast<std::size_t>(l.kp)]);
  if (has_z) tz = std::clamp(tz, l.lower[static_cast<std::size_t>(l.tz)], l.upper[static_cast<std::size_t>(l.tz)]);
  v[static_cast<std::size_t>(l.kp)] = kp;
  if (has_z) v[static_cast<std::size_t>(l.tz)] = tz;
  start.values = v;
  double cost = 0.0;
  for (std::size_t e = 0; e < prep.size(); ++e) {
    const Local& loc = locals[e];
    const Prepared& p = prep[e];
    Eigen::VectorXd be(loc.a.cols());
    be.head(m_shared) = beta.head(m_shared);
    be.tail(loc.a.cols() - m_shared) = beta.segment(loc.offset, loc.a.cols() - m_shared);
    cost += 0.5 * (loc.b - loc.a * be).squaredNorm();
    std::vector<double> nuis;
    if (p.x0) {
      // Basis coefficients a give c0 Φᵏ a; the model's free response is c Φᵏ x0 with
      // c = Kp (c0 + Tz c1): x0 = O⁻¹ O₀ a (observability matrices).
      const Eigen::VectorXd a = be.segment(m_shared, n);
      const Eigen::RowVectorXd c_full = kp * (loc.s0.c + tz * loc.c1);
      Eigen::MatrixXd o(n, n), o0(n, n);
      Eigen::RowVectorXd r_full = c_full, r0 = loc.s0.c;
      for (int i = 0; i < n; ++i) {
        o.row(i) = r_full;
        o0.row(i) = r0;
        r_full = r_full * loc.s0.phi;
        r0 = r0 * loc.s0.phi;
      }
      Eigen::FullPivLU<Eigen::MatrixXd> lu(o);
      Eigen::VectorXd x0 = Eigen::VectorXd::Zero(n);
      if (lu.rank() == n) x0 = lu.solve(o0 * a);
      for (int i = 0; i < n; ++i) nuis.push_back(x0(i));
    }
    if (p.u0) nuis.push_back(0.0);
    if (p.y0) nuis.push_back(be(be.size() - 1));
    start.nuisance.push_back(nuis);
  }
  start.cost = cost;
  if (!std::isfinite(cost)) return std::nullopt;
  return start;
}

struct Run {
  std::vector<double> theta;
  std::vector<std::vector<double>> nuisance;
  double cost = 0.0;
  std::size_t iterations = 0;
  bool converged = false;
};

void add_blocks(ceres::Problem& problem, const Layout& l, const std::vector<Prepared>& prep, int n, ModelCache& cache,
                Run& run) {
  for (std::size_t e = 0; e < prep.size(); ++e) {
    std::vector<double*> blocks;
    if (!l.free.empty()) blocks.push_back(run.theta.data());
    if (!run.nuisance[e].empty()) blocks.push_back(run.nuisance[e].data());
    problem.AddResidualBlock(new ExperimentCost(l, prep[e], n, cache), nullptr, blocks);
  }
  if (l.free.empty()) return;
  for (std::size_t slot = 0; slot < l.free.size(); ++slot) {
    const auto p = static_cast<std::size_t>(l.free[slot]);
    double lo = l.lower[p], hi = l.upper[p];
    if (l.log_scale[p]) {
      lo = lo > 0.0 ? std::log(lo) : -std::numeric_limits<double>::infinity();
      hi = hi > 0.0 && std::isfinite(hi) ? std::log(hi) : std::numeric_limits<double>::infinity();
    }
    const int i = static_cast<int>(slot);
    run.theta[slot] = std::clamp(run.theta[slot], lo, hi);
    if (std::isfinite(lo)) problem.SetParameterLowerBound(run.theta.data(), i, lo);
    if (std::isfinite(hi)) problem.SetParameterUpperBound(run.theta.data(), i, hi);
  }
}

Run run_lm(const Layout& l, const std::vector<Prepared>& prep, int n, const Start& start, std::size_t max_iterations,
           ModelCache& cache) {
  Run run;
  run.theta = l.theta(start.values);
  run.nuisance = start.nuisance;
  bool any_nuisance = false;
  for (const auto& v : run.nuisance) any_nuisance = any_nuisance || !v.empty();
  if (l.free.empty() && !any_nuisance) {
    run.cost = start.cost;
    run.converged = true;
    return run;
  }
  ceres::Problem problem;
  add_blocks(problem, l, prep, n, cache, run);
  ceres::Solver::Options so;
  so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = static_cast<int>(max_iterations);
  so.function_tolerance = 1e-12;
  so.gradient_tolerance = 1e-14;
  so.parameter_tolerance = 1e-11;
  so.logging_type = ceres::SILENT;
  so.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  run.cost = summary.final_cost;
  run.iterations = summary.iterations.size();
  run.converged = summary.termination_type == ceres::CONVERGENCE;
  return run;
}

// Covariance of the free plant parameters in optimizer variables: (JᵀJ)⁻¹σ², or the sandwich
// for a coloured residual (covariance.hpp); p counts every free parameter.
Eigen::MatrixXd theta_covariance(const Layout& l, const std::vector<Prepared>& prep, int n, ModelCache& cache, Run run,
                                 double sigma2, std::size_t p) {
  const auto np = static_cast<Eigen::Index>(l.free.size());
  Eigen::MatrixXd out = Eigen::MatrixXd::Constant(np, np, kNaN);
  if (np == 0) return out;
  ceres::Problem problem;
  add_blocks(problem, l, prep, n, cache, run);
  std::vector<double*> blocks{run.theta.data()};
  for (auto& v : run.nuisance)
    if (!v.empty()) blocks.push_back(v.data());
  const Eigen::MatrixXd full = detail::parameter_covariance(problem, blocks, sigma2, p);  // θ first, then the nuisance
  out = full.topLeftCorner(np, np);
  return out;
}

double log_distance(const Layout& l, const std::vector<double>& a, const std::vector<double>& b) {
  double d = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!l.log_scale[i]) continue;
    d = std::max(d, std::abs(std::log(a[i]) - std::log(b[i])));
  }
  return d;
}

double variance(const std::vector<double>& v) {
  const double mean = std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
  double s = 0.0;
  for (double x : v) s += (x - mean) * (x - mean);
  return s / static_cast<double>(v.size());
}

struct Search {
  Run best;
  std::size_t candidates = 0;
  std::size_t iterations = 0;
};

// Multi-start search: rank every data-derived candidate with its linear parameters solved, run
// Levenberg–Marquardt from the best distinct ones (and a user-given start), keep the lowest cost,
// report it in canonical form.
Search search(const Layout& layout, const std::vector<Prepared>& prep, int n, std::span<const Experiment> experiments,
              const ProcessFitOptions& options, ModelCache& cache) {
  if (!options.search) {  // refine from the given values: linear nuisance start, one LM run
    std::vector<double> v(layout.names.size());
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (layout.is_fixed(static_cast<int>(i))) {
        v[i] = layout.fixed_value[i];
      } else if (layout.initial[i]) {
        v[i] = *layout.initial[i];
      } else {
        throw InvalidArgument("process fit without search: parameter " + layout.names[i] + " of " +
                              layout.structure.code() + " has no initial value; give one or enable the search.");
      }
    }
    auto s = rank(layout, prep, v, options.hold, n);
    if (!s) throw RuntimeError("process fit: the initial model gives no finite simulated output.");
    s->values = v;
    Search out;
    out.candidates = 1;
    out.best = run_lm(layout, prep, n, *s, options.max_iterations, cache);
    out.iterations = out.best.iterations;
    return out;
  }
  // Rank the candidates with the linear parameters solved, keep the best distinct ones.
  std::vector<Start> ranked;
  for (auto& v : detail::candidate_values(layout, experiments)) {
    if (auto s = rank(layout, prep, v, options.hold, n)) ranked.push_back(std::move(*s));
  }
  if (ranked.empty()) {
    throw RuntimeError("process fit of " + layout.structure.code() + ": no starting point gives a finite simulated output; "
                       "check the data (input and output columns, units) or fix some parameters.");
  }
  std::stable_sort(ranked.begin(), ranked.end(), [](const Start& a, const Start& b) { return a.cost < b.cost; });
  std::vector<Start> starts;
  const std::size_t wanted = std::max<std::size_t>(1, options.starts);
  for (const auto& s : ranked) {
    bool distinct = true;
    for (const auto& t : starts) distinct = distinct && log_distance(layout, s.values, t.values) > 0.1;
    if (distinct) starts.push_back(s);
    if (starts.size() == wanted) break;
  }
  // A user-given initial value: the best candidate with those values substituted.
  bool user_initial = false;
  std::vector<double> user = ranked.front().values;
  for (std::size_t i = 0; i < layout.names.size(); ++i) {
    if (layout.initial[i]) {
      user[i] = *layout.initial[i];
      user_initial = true;
    }
  }
  if (user_initial) {
    if (auto s = rank(layout, prep, user, options.hold, n)) {
      for (std::size_t i = 0; i < layout.names.size(); ++i)
        if (layout.initial[i]) s->values[i] = *layout.initial[i];
      starts.push_back(*s);
    }
  }

  Search out;
  out.candidates = ranked.size();
  Run& best = out.best;
  best.cost = std::numeric_limits<double>::infinity();
  std::size_t& iterations = out.iterations;
  for (const auto& s : starts) {
    Run r = run_lm(layout, prep, n, s, options.max_iterations, cache);
    iterations += r.iterations;
    if (r.cost < best.cost) best = std::move(r);
  }
  if (!std::isfinite(best.cost)) throw RuntimeError("process fit of " + layout.structure.code() + " diverged from every start.");
  // Equivalent parameter sets (exchangeable real poles) are reported in canonical form: refit
  // from it (same transfer function, so the cost is unchanged) to get its covariance.
  const std::vector<double> found = layout.values(best.theta.data());
  const std::vector<double> canon = detail::canonical(layout, found);
  if (canon != found) {
    if (auto s = rank(layout, prep, canon, options.hold, n)) {
      s->values = canon;
      Run r = run_lm(layout, prep, n, *s, options.max_iterations, cache);
      iterations += r.iterations;
      if (r.cost <= best.cost * (1.0 + 1e-6) + 1e-300) best = std::move(r);
    }
  }

  return out;
}

// F test of a free initial state at a zero-state optimum: regress the residual on the free-
// response columns C Φᵏ; significant when F = ((V0 − V1)/n)/(V1/(N − n)) exceeds the χ²ₙ/n
// quantile at 1 − 10⁻⁶ (n = 1…4: 23.9, 13.8, 10.2, 8.4).
bool initial_state_significant(const Sampled& m, const Prepared& p, const Nuisance& nu, int n) {
  Prepared probe = p;
  probe.x0 = true;
  probe.u0 = probe.y0 = false;
  Nuisance at = nu;
  at.x0.assign(static_cast<std::size_t>(n), 0.0);
  const std::size_t count = p.e->size();
  std::vector<double> y(count), cols(count * static_cast<std::size_t>(n)), u;
  if (!simulate_experiment(m, probe, at, {}, {}, u, y.data(), cols.data())) return false;
  Eigen::MatrixXd a(static_cast<Eigen::Index>(count), n);
  Eigen::VectorXd r(static_cast<Eigen::Index>(count));
  for (std::size_t k = 0; k < count; ++k) {
    r(static_cast<Eigen::Index>(k)) = p.e->output[k] - y[k];
    for (int i = 0; i < n; ++i) a(static_cast<Eigen::Index>(k), i) = cols[k * static_cast<std::size_t>(n) + static_cast<std::size_t>(i)];
  }
  const double v0 = r.squaredNorm();
  const double v1 = (r - a * a.colPivHouseholderQr().solve(r)).squaredNorm();
  static constexpr double kQuantile[5] = {0.0, 23.9, 13.8, 10.2, 8.4};
  if (!(v1 > 0.0)) return v0 > 0.0;
  const double f = ((v0 - v1) / n) / (v1 / static_cast<double>(count - static_cast<std::size_t>(n)));
  return f > kQuantile[std::min(n, 4)];
}

}  // namespace

double ProcessEstimate::fit_percent() const {
  if (experiments.empty()) return kNaN;
  double s = 0.0;
  for (const auto& e : experiments) s += e.fit_percent;
  return s / static_cast<double>(experiments.size());
}

const ParameterEstimate& ProcessEstimate::parameter(std::string_view name) const {
  for (const auto& p : parameters)
    if (p.name == name) return p;
  throw InvalidArgument("process estimate of " + model.code() + " has no parameter \"" + std::string(name) + "\".");
}

std::optional<double> ProcessEstimate::natural_frequency_rad_s() const {
  if (!model.structure().underdamped) return std::nullopt;
  return 1.0 / parameter("Tw").value;  // thesis §4.2: ωn = 1/Tw
}
std::optional<double> ProcessEstimate::natural_frequency_std_rad_s() const {
  if (!model.structure().underdamped) return std::nullopt;
  const auto& tw = parameter("Tw");
  return tw.std_dev / (tw.value * tw.value);  // |d(1/Tw)/dTw| σ
}
std::optional<double> ProcessEstimate::damping_ratio() const {
  if (!model.structure().underdamped) return std::nullopt;
  return parameter("Zeta").value;  // thesis §4.2: ξ = Zeta
}
std::optional<double> ProcessEstimate::damping_ratio_std() const {
  if (!model.structure().underdamped) return std::nullopt;
  return parameter("Zeta").std_dev;
}

ProcessEstimate estimate_process_model(const lti::ProcessStructure& structure, std::span<const Experiment> experiments,
                                       const ProcessFitOptions& options) {
  (void)lti::ProcessStructure::parse(structure.code());
  if (experiments.empty()) throw InvalidArgument("estimate_process_model: no experiments; give at least one record.");
  double shortest = std::numeric_limits<double>::infinity();
  for (const auto& e : experiments) {
    validate(e);
    shortest = std::min(shortest, e.duration_s());
  }
  const double max_delay = options.max_delay_s > 0.0 ? options.max_delay_s : 0.25 * shortest;
  const Layout layout = detail::make_layout(structure, options, max_delay);
  const int n = detail::process_order(structure);

  std::vector<Prepared> prep(experiments.size());
  for (std::size_t i = 0; i < experiments.size(); ++i) {
    const Experiment& e = experiments[i];
    const double var = variance(e.output);
    if (!(var > 0.0)) {
      throw InvalidArgument("experiment \"" + e.name + "\": the output is constant; nothing to identify.");
    }
    Prepared& p = prep[i];
    p.e = &e;
    p.weight = 1.0 / std::sqrt(static_cast<double>(e.size()) * var);
    p.u0 = options.estimate_input_offset;
    p.y0 = options.estimate_output_offset;
    switch (options.initial_state) {
      case InitialState::zero: p.x0 = false; break;
      case InitialState::estimate: p.x0 = true; break;
      case InitialState::automatic: p.x0 = !detail::starts_at_rest(e.output, options.estimate_output_offset); break;
    }
    if (n == 0) p.x0 = false;
  }

  ModelCache cache(structure, options.hold);
  Search found = search(layout, prep, n, experiments, options, cache);
  if (options.initial_state == InitialState::automatic && n > 0) {
    // Records that passed the level test were fitted from rest; an F test at that optimum asks
    // whether a free initial state would explain significantly more (a record cut mid-motion).
    bool refit = false;
    const std::vector<double> values = layout.values(found.best.theta.data());
    for (std::size_t e = 0; e < prep.size(); ++e) {
      if (prep[e].x0) continue;
      const Nuisance nu = split(prep[e], n, found.best.nuisance[e].data());
      if (initial_state_significant(cache.get(values, prep[e].e->sample_time_s, false), prep[e], nu, n)) {
        prep[e].x0 = true;
        refit = true;
      }
    }
    if (refit) found = search(layout, prep, n, experiments, options, cache);
  }
  const std::size_t candidates = found.candidates;
  std::size_t iterations = found.iterations;
  Run best = std::move(found.best);

  // ---------------------------------------------------------------- results
  ProcessEstimate out;
  out.candidates = candidates;
  out.iterations = iterations;
  out.converged = best.converged;
  out.weighted_cost = best.cost;
  const std::vector<double> values = layout.values(best.theta.data());
  lti::ProcessParameters params;
  for (std::size_t i = 0; i < values.size(); ++i) params.set(layout.names[i], values[i]);
  out.model = lti::ProcessModel(structure, params);

  std::size_t total = 0, p_total = layout.free.size();
  for (const auto& p : prep) {
    total += p.e->size();
    p_total += p.nuisance(n);
  }
  out.samples = total;
  out.free_parameters = p_total;
  const double sigma2 = total > p_total ? 2.0 * best.cost / static_cast<double>(total - p_total) : kNaN;
  const Eigen::MatrixXd cov_theta = theta_covariance(layout, prep, n, cache, best, sigma2, p_total);
  const std::vector<double> chain = layout.chain(best.theta.data());
  const auto np = static_cast<Eigen::Index>(layout.free.size());
  out.covariance.resize(np, np);
  for (Eigen::Index i = 0; i < np; ++i)
    for (Eigen::Index j = 0; j < np; ++j)
      out.covariance(i, j) = cov_theta(i, j) * chain[static_cast<std::size_t>(i)] * chain[static_cast<std::size_t>(j)];
  for (int p : layout.free) out.free_names.push_back(layout.names[static_cast<std::size_t>(p)]);
  for (std::size_t i = 0; i < values.size(); ++i) {
    ParameterEstimate pe;
    pe.name = layout.names[i];
    pe.value = values[i];
    pe.fixed = layout.is_fixed(static_cast<int>(i));
    if (!pe.fixed) {
      const auto on = [&](double bound) { return std::isfinite(bound) && std::abs(pe.value - bound) <= 1e-6 * std::max(std::abs(bound), 1e-9); };
      pe.at_bound = on(layout.lower[i]) || on(layout.upper[i]);
    }
    for (std::size_t slot = 0; slot < layout.free.size(); ++slot) {
      if (layout.free[slot] == static_cast<int>(i)) {
        const auto s = static_cast<Eigen::Index>(slot);
        pe.std_dev = std::sqrt(std::max(0.0, out.covariance(s, s)));
        if (!std::isfinite(out.covariance(s, s))) pe.std_dev = kNaN;
      }
    }
    out.parameters.push_back(pe);
  }

  double sse = 0.0;
  for (std::size_t e = 0; e < prep.size(); ++e) {
    const Prepared& p = prep[e];
    const Experiment& ex = *p.e;
    const std::size_t count = ex.size();
    const Nuisance nu = split(p, n, best.nuisance[e].data());
    const Sampled& m = cache.get(values, ex.sample_time_s, false);
    std::vector<double> y(count), u;
    simulate_experiment(m, p, nu, {}, {}, u, y.data(), nullptr);
    ExperimentFit f;
    f.name = ex.name;
    f.fit_percent = metrics::fit_percent(ex.output, y);
    f.rmse = metrics::rmse(ex.output, y);
    for (std::size_t k = 0; k < count; ++k) sse += (ex.output[k] - y[k]) * (ex.output[k] - y[k]);
    f.initial_state = nu.x0.empty() ? Eigen::VectorXd::Zero(n)
                                    : Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(nu.x0.data(), n));
    f.output_offset = nu.y0;
    f.input_offset = nu.u0;
    f.simulated = UniformSeries{0.0, ex.sample_time_s, y};
    // The same model from rest, and with x0 refitted by least squares (compare's default).
    CompareOptions co;
    co.hold = options.hold;
    co.input_offset = nu.u0;
    co.estimate_output_offset = p.y0;
    co.initial_state = InitialState::zero;
    f.fit_percent_zero_ic = compare(out.model, ex, co).fit_percent;
    co.initial_state = InitialState::estimate;
    f.fit_percent_estimated_ic = compare(out.model, ex, co).fit_percent;
    out.experiments.push_back(std::move(f));
  }
  out.loss = sse / static_cast<double>(total);
  const double pn = static_cast<double>(p_total) / static_cast<double>(total);
  const double nn = static_cast<double>(total);
  out.fpe = out.loss * (1.0 + pn) / (1.0 - pn);                                    // Akaike FPE
  out.aic = nn * std::log(out.loss) + 2.0 * static_cast<double>(p_total);          // Akaike 1974
  out.bic = nn * std::log(out.loss) + static_cast<double>(p_total) * std::log(nn);  // Schwarz 1978
  return out;
}

ExperimentFit compare(const lti::ProcessModel& model, const Experiment& experiment, const CompareOptions& options) {
  validate(experiment);
  require_finite("compare input_offset", options.input_offset);
  const lti::SampledModel sm(model, experiment.sample_time_s, options.hold);
  UniformSeries u{0.0, experiment.sample_time_s, experiment.input};
  for (double& v : u.values) v -= options.input_offset;
  const UniformSeries y_zero = lti::simulate(sm, u);
  const std::size_t count = experiment.size();
  const Eigen::Index n = sm.order();
  bool estimate_x0 = options.initial_state == InitialState::estimate;
  if (options.initial_state == InitialState::automatic) {
    estimate_x0 = !detail::starts_at_rest(experiment.output, options.estimate_output_offset);
  }
  if (n == 0) estimate_x0 = false;
  // Free response columns C Φᵏ (lti's realization) and the offset column, fitted by least squares.
  const Eigen::Index cols = (estimate_x0 ? n : 0) + (options.estimate_output_offset ? 1 : 0);
  Eigen::VectorXd coef = Eigen::VectorXd::Zero(cols);
  Eigen::MatrixXd a(static_cast<Eigen::Index>(count), cols);
  if (cols > 0) {
    Eigen::RowVectorXd r = sm.c().row(0);
    Eigen::VectorXd b(static_cast<Eigen::Index>(count));
    for (std::size_t k = 0; k < count; ++k) {
      const auto kk = static_cast<Eigen::Index>(k);
      Eigen::Index c = 0;
      if (estimate_x0) {
        a.block(kk, 0, 1, n) = r;
        c += n;
        r = r * sm.phi();
      }
      if (options.estimate_output_offset) a(kk, c) = 1.0;
      b(kk) = experiment.output[k] - y_zero.values[k];
    }
    coef = a.colPivHouseholderQr().solve(b);
  }
  ExperimentFit f;
  f.name = experiment.name;
  std::vector<double> y = y_zero.values;
  if (cols > 0) {
    const Eigen::VectorXd extra = a * coef;
    for (std::size_t k = 0; k < count; ++k) y[k] += extra(static_cast<Eigen::Index>(k));
  }
  f.initial_state = estimate_x0 ? Eigen::VectorXd(coef.head(n)) : Eigen::VectorXd::Zero(n);
  f.output_offset = options.estimate_output_offset ? coef(cols - 1) : 0.0;
  f.input_offset = options.input_offset;
  f.fit_percent = metrics::fit_percent(experiment.output, y);
  f.rmse = metrics::rmse(experiment.output, y);
  if (estimate_x0) {
    f.fit_percent_estimated_ic = f.fit_percent;
  } else {
    f.fit_percent_zero_ic = f.fit_percent;
  }
  f.simulated = UniformSeries{0.0, experiment.sample_time_s, std::move(y)};
  return f;
}

}  // namespace clearshape::ident
