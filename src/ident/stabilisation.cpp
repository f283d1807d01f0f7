#include "clearshape/ident/stabilisation.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <set>
#include <string>

#include <Eigen/Dense>

#include "clearshape/core/error.hpp"
#include "clearshape/core/linalg.hpp"
#include "clearshape/ident/subspace.hpp"
#include "decimation.hpp"

namespace clearshape::ident {

double DiagramPole::frequency_hz() const noexcept { return natural_frequency_rad_s / (2.0 * std::numbers::pi); }
double PersistentMode::frequency_hz() const noexcept { return natural_frequency_rad_s / (2.0 * std::numbers::pi); }

bool matches(const PersistentMode& mode, double natural_frequency_rad_s, double tolerance) {
  return std::abs(natural_frequency_rad_s - mode.natural_frequency_rad_s) <= tolerance * mode.natural_frequency_rad_s;
}

namespace {

// Spectral peaks that set the free response's block averaging: the dominant few (a fixed count, so
// that the diagram never depends on how many modes are to be reported) within 20 dB of the highest
// (a noise bump of the periodogram does not undo the averaging).
constexpr std::size_t kDecimationPeaks = 4;
constexpr double kDecimationRelativePower = 0.01;
// A pole at ≥ 90 % of the Nyquist frequency (θ ≥ 0.9π) is no mode the record resolves.
constexpr double kNyquistFraction = 0.9;

void check(const StabilisationOptions& o) {
  if (o.min_order < 2) throw_invalid("stabilisation min_order", static_cast<double>(o.min_order), ">= 2");
  if (o.max_order <= o.min_order) {
    throw_invalid("stabilisation max_order", static_cast<double>(o.max_order),
                  "> min_order (" + std::to_string(o.min_order) + ")", "The diagram needs at least two orders.");
  }
  require_in_open("stabilisation frequency_tolerance", o.frequency_tolerance, 0.0, 0.5);
  require_in_open("stabilisation damping_tolerance", o.damping_tolerance, 0.0, 10.0);
  if (!(o.amplitude_tolerance >= 0.0)) throw_invalid("stabilisation amplitude_tolerance", o.amplitude_tolerance, ">= 0");
  require_in_open("stabilisation max_damping_ratio", o.max_damping_ratio, 0.0, 1.0 + 1e-12);
  if (o.min_stable_orders < 1) throw_invalid("stabilisation min_stable_orders", 0.0, ">= 1");
  require_in_open("stabilisation min_stable_fraction", o.min_stable_fraction, 0.0, 1.0 + 1e-12);
  if (!(o.min_relative_amplitude >= 0.0 && o.min_relative_amplitude < 1.0)) {
    throw_invalid("stabilisation min_relative_amplitude", o.min_relative_amplitude, "[0, 1)");
  }
}

// Complex pole pairs of x[k+1] = A x[k], y = c x with input/initial-state vector v: residue of
// pole λᵢ is (c wᵢ)(W⁻¹ v)ᵢ (eigenvectors W); s = ln z / T (ZOH-exact), ωn = |s|, ζ = −Re s/|s|.
std::vector<DiagramPole> modal_poles(const Eigen::MatrixXd& a, const Eigen::RowVectorXd& c, const Eigen::VectorXd& v,
                                     double sample_time_s) {
  const linalg::EigenDecomposition es = linalg::eigen(a, true);
  const Eigen::MatrixXcd& w = es.vectors;
  const Eigen::VectorXcd weights = w.fullPivLu().solve(v.cast<std::complex<double>>());
  const Eigen::RowVectorXcd cw = c.cast<std::complex<double>>() * w;
  std::vector<DiagramPole> poles;
  for (Eigen::Index k = 0; k < es.values.size(); ++k) {
    const std::complex<double> z = es.values(k);
    if (!(z.imag() > 1e-10 * std::max(1.0, std::abs(z))) || std::arg(z) >= kNyquistFraction * std::numbers::pi) continue;
    const std::complex<double> s = std::log(z) / sample_time_s;
    DiagramPole p;
    p.natural_frequency_rad_s = std::abs(s);
    p.damping_ratio = -s.real() / std::abs(s);
    p.amplitude = 2.0 * std::abs(cw(k) * weights(k));
    poles.push_back(p);
  }
  std::sort(poles.begin(), poles.end(),
            [](const DiagramPole& x, const DiagramPole& y) { return x.natural_frequency_rad_s < y.natural_frequency_rad_s; });
  return poles;
}

double relative_change(double now, double before) { return std::abs(now - before) / std::max(std::abs(before), 1e-300); }

// Flags of one order against the previous: the nearest pole in frequency is its predecessor.
void flag_against(DiagramOrder& now, const DiagramOrder& before, const StabilisationOptions& o) {
  for (DiagramPole& p : now.poles) {
    p.physical = p.damping_ratio > 0.0 && p.damping_ratio < o.max_damping_ratio;
    const DiagramPole* near = nullptr;
    for (const DiagramPole& q : before.poles)
      if (near == nullptr || std::abs(q.natural_frequency_rad_s - p.natural_frequency_rad_s) <
                                 std::abs(near->natural_frequency_rad_s - p.natural_frequency_rad_s))
        near = &q;
    if (near == nullptr) continue;
    p.stable_frequency = relative_change(p.natural_frequency_rad_s, near->natural_frequency_rad_s) < o.frequency_tolerance;
    p.stable_damping = p.stable_frequency && relative_change(p.damping_ratio, near->damping_ratio) < o.damping_tolerance;
    const bool residue_ok = o.amplitude_tolerance <= 0.0 || relative_change(p.amplitude, near->amplitude) < o.amplitude_tolerance;
    p.stable = p.stable_damping && residue_ok && p.physical;
  }
}

bool persistent_pole(const DiagramPole& p, const StabilisationOptions& o) {
  return o.persistence_needs_damping.value_or(true) ? p.stable : p.stable_frequency && p.physical;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 == 1 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

struct StablePole {
  double wn, zeta;
  std::size_t order;
};

// Stable poles in chains of neighbours closer than the frequency tolerance; a chain holding stable
// poles of at least min_stable_orders orders, and of min_stable_fraction of the orders from its
// first one up, is a persistent mode (medians of its poles). A noise pole is stable now and then;
// a physical one at every order once the model is large enough to hold it.
std::vector<PersistentMode> persistent_modes(const std::vector<DiagramOrder>& orders, const StabilisationOptions& o) {
  std::vector<StablePole> stable;
  for (const DiagramOrder& d : orders) {
    double largest = 0.0;
    for (const DiagramPole& p : d.poles) largest = std::max(largest, p.amplitude);
    for (const DiagramPole& p : d.poles)
      if (persistent_pole(p, o) && p.amplitude >= o.min_relative_amplitude * largest)
        stable.push_back({p.natural_frequency_rad_s, p.damping_ratio, d.order});
  }
  std::sort(stable.begin(), stable.end(), [](const StablePole& x, const StablePole& y) { return x.wn < y.wn; });
  std::vector<PersistentMode> modes;
  std::size_t first = 0;
  for (std::size_t k = 1; k <= stable.size(); ++k) {
    if (k < stable.size() && relative_change(stable[k].wn, stable[k - 1].wn) < o.frequency_tolerance) continue;
    std::vector<double> wn, zeta;
    std::set<std::size_t> in_orders;
    for (std::size_t j = first; j < k; ++j) {
      wn.push_back(stable[j].wn);
      zeta.push_back(stable[j].zeta);
      in_orders.insert(stable[j].order);
    }
    const auto from = std::count_if(orders.begin(), orders.end(), [&](const DiagramOrder& d) {
      return !in_orders.empty() && d.order >= *in_orders.begin();
    });
    const bool persists = in_orders.size() >= o.min_stable_orders &&
                          static_cast<double>(in_orders.size()) >= o.min_stable_fraction * static_cast<double>(from);
    if (persists) modes.push_back({median(wn), median(zeta), in_orders.size()});
    first = k;
  }
  return modes;
}

std::size_t present(const DiagramOrder& d, const std::vector<PersistentMode>& modes, const StabilisationOptions& o) {
  std::size_t count = 0;
  for (const PersistentMode& m : modes) {
    const bool found = std::any_of(d.poles.begin(), d.poles.end(), [&](const DiagramPole& p) {
      return persistent_pole(p, o) && matches(m, p.natural_frequency_rad_s, o.frequency_tolerance);
    });
    count += found ? 1 : 0;
  }
  return count;
}

// The lowest order at which every persistent mode is a stable pole (else the one holding most).
std::size_t choose_order(const std::vector<DiagramOrder>& orders, const std::vector<PersistentMode>& modes,
                         const StabilisationOptions& o) {
  std::size_t best = 0, best_count = 0;
  for (const DiagramOrder& d : orders) {
    const std::size_t count = present(d, modes, o);
    if (count > best_count) {
      best = d.order;
      best_count = count;
    }
    if (count == modes.size()) break;
  }
  return best;
}

}  // namespace

StabilisationDiagram build_stabilisation_diagram(std::vector<DiagramOrder> orders, const StabilisationOptions& options) {
  check(options);
  StabilisationDiagram out;
  out.options = options;
  out.options.persistence_needs_damping = options.persistence_needs_damping.value_or(true);
  for (std::size_t j = 1; j < orders.size(); ++j) flag_against(orders[j], orders[j - 1], options);
  out.orders = std::move(orders);
  out.modes = persistent_modes(out.orders, out.options);
  out.chosen_order = choose_order(out.orders, out.modes, out.options);
  return out;
}

StabilisationDiagram free_response_stabilisation(const UniformSeries& response, const StabilisationOptions& options) {
  check(options);
  require_positive("response sample_time_s", response.sample_time_s);
  if (response.size() < 50) {
    throw InvalidArgument("free response has " + std::to_string(response.size()) +
                          " samples; at least 50 are needed for a stabilisation diagram.");
  }
  const std::size_t q = detail::choose_decimation(response.values, kDecimationPeaks, options.max_order, kDecimationRelativePower);
  const std::vector<double> averaged = detail::block_average(response.values, q);
  const std::size_t rows = std::min(averaged.size() / 3, std::max<std::size_t>(4 * options.max_order, 40));
  const std::size_t top = std::min(options.max_order, rows - 1);
  const std::vector<FreeResponseModel> models = era_orders(averaged, options.min_order, top, rows);
  std::vector<DiagramOrder> orders;
  for (std::size_t n = options.min_order; n <= top; ++n) {
    const FreeResponseModel& m = models[n - options.min_order];
    orders.push_back({n, modal_poles(m.a, m.c, m.x0, response.sample_time_s * static_cast<double>(q))});
  }
  StabilisationDiagram out = build_stabilisation_diagram(std::move(orders), options);
  out.decimation = q;
  return out;
}

StabilisationDiagram input_output_stabilisation(const Experiment& experiment, const StabilisationOptions& options) {
  check(options);
  validate(experiment, 50);
  // One horizon i for every order (the same projection, truncated at each order), data permitting:
  // N ≥ 2i + 2·order + 10.
  const std::size_t n_samples = experiment.output.size();
  std::size_t top = options.max_order;
  while (top > options.min_order && n_samples < 2 * std::max<std::size_t>(2 * top, 10) + 2 * top + 10) --top;
  SubspaceOptions so;
  so.block_rows = std::max<std::size_t>(2 * top, 10);
  const std::vector<SubspaceModel> models = n4sid_orders(experiment, options.min_order, top, so);
  std::vector<DiagramOrder> orders;
  for (std::size_t n = options.min_order; n <= top; ++n) {
    const SubspaceModel& m = models[n - options.min_order];
    DiagramOrder d{n, {}};  // an order the data do not support: an empty column
    if (m.model.a.size() > 0) d.poles = modal_poles(m.model.a, m.model.c, m.model.b.col(0), experiment.sample_time_s);
    orders.push_back(std::move(d));
  }
  StabilisationOptions io = options;  // frequency persistence unless asked otherwise (stabilisation.hpp)
  io.persistence_needs_damping = options.persistence_needs_damping.value_or(false);
  return build_stabilisation_diagram(std::move(orders), io);
}

}  // namespace clearshape::ident
