#include "clearshape/export/c_header.hpp"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/version.hpp"
#include "clearshape/export/numbers.hpp"
#include "clearshape/shaping/residual.hpp"

namespace clearshape::exports {

namespace sh = clearshape::shaping;

namespace {

bool is_c_identifier(const std::string& s) {
  if (s.empty() || s.size() > 31) return false;  // 31: C99's guaranteed significant length
  if (!(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  return std::all_of(s.begin(), s.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

template <typename T, typename F>
std::string braced(const std::vector<T>& values, F&& format_one) {
  std::string out = "{";
  for (std::size_t j = 0; j < values.size(); ++j) out += (j ? ", " : " ") + format_one(values[j]);
  return out + " }";
}

// The step function body shared by double and float: the arithmetic of StreamingShaper::step
// (src/shaping/streaming.cpp) in the same order — hold a non-finite input, advance the head,
// store, two accumulators over even and odd taps, then even + odd.
std::string float_step(const std::string& p, const std::string& P, const std::string& type, const std::string& taps_macro,
                       const std::string& zero) {
  return fmt::format(
      R"(/* Resets the history to `value`, as if the input had rested there forever. */
static inline void {p}_reset_{t}({p}_state_{t} *s, {t} value)
{{
  {p}_index_t i;
  for (i = 0u; i < {P}_HISTORY; ++i) s->history[i] = value;
  s->head = 0u;
}}

/* Pushes one input sample and returns the shaped output. A non-finite input is replaced by the
 * previous input (the output stays finite and continuous). O({P}_TAPS), no allocation. */
static inline {t} {p}_step_{t}({p}_state_{t} *s, {t} input)
{{
  static const {p}_index_t delay[{P}_TAPS] = {P}_DELAYS;
  static const {t} w[{P}_TAPS] = {taps};
  {t} even = {z};
  {t} odd = {z};
  {p}_index_t j;
  if (!isfinite(input)) input = s->history[s->head];
  s->head = ({p}_index_t)((s->head + 1u) & {P}_MASK);
  s->history[s->head] = input;
  for (j = 0u; j + 1u < {P}_TAPS; j += 2u) {{
    even += w[j] * s->history[({p}_index_t)(s->head - delay[j]) & {P}_MASK];
    odd += w[j + 1u] * s->history[({p}_index_t)(s->head - delay[j + 1u]) & {P}_MASK];
  }}
  if (j < {P}_TAPS) even += w[j] * s->history[({p}_index_t)(s->head - delay[j]) & {P}_MASK];
  return even + odd;
}}

)",
      fmt::arg("p", p), fmt::arg("P", P), fmt::arg("t", type), fmt::arg("taps", taps_macro), fmt::arg("z", zero));
}

// Integer step: exact accumulation in `acc_type`, then round half away from zero by division
// (defined behaviour in C99 for negative values, unlike >> on a negative number).
std::string fixed_step(const std::string& p, const std::string& P, const std::string& suffix, const std::string& sample_type,
                       const std::string& acc_type, const std::string& taps_macro, const std::string& half,
                       const std::string& one) {
  return fmt::format(
      R"(/* Resets the history to `value`. */
static inline void {p}_reset_{s}({p}_state_{s} *st, {x} value)
{{
  {p}_index_t i;
  for (i = 0u; i < {P}_HISTORY; ++i) st->history[i] = value;
  st->head = 0u;
}}

/* Pushes one input sample (any integer unit: counts, DAC codes, Q-format) and returns the shaped
 * output in the same unit. The accumulation is exact; the result is rounded half away from zero. */
static inline {x} {p}_step_{s}({p}_state_{s} *st, {x} input)
{{
  static const {p}_index_t delay[{P}_TAPS] = {P}_DELAYS;
  static const {x} w[{P}_TAPS] = {taps};
  {a} acc = 0;
  {p}_index_t j;
  st->head = ({p}_index_t)((st->head + 1u) & {P}_MASK);
  st->history[st->head] = input;
  for (j = 0u; j < {P}_TAPS; ++j) {{
    acc += ({a})w[j] * ({a})st->history[({p}_index_t)(st->head - delay[j]) & {P}_MASK];
  }}
  return ({x})((acc >= 0 ? acc + {half} : acc - {half}) / {one});
}}

)",
      fmt::arg("p", p), fmt::arg("P", P), fmt::arg("s", suffix), fmt::arg("x", sample_type), fmt::arg("a", acc_type),
      fmt::arg("taps", taps_macro), fmt::arg("half", half), fmt::arg("one", one));
}

std::string short_number(double x) { return fmt::format("{:.6g}", x); }

// What the header is made of: the taps, their bounds, the ring size and the names.
struct HeaderPlan {
  std::vector<sh::DiscreteTap> taps;
  CHeaderBounds bounds;
  std::size_t max_delay = 0;
  std::size_t history = 0;  ///< ring size: a power of two > max_delay
  std::string p, P;         ///< the C name and its upper-case macro prefix
  bool fixed = false;       ///< Q15/Q31 taps generated
};

HeaderPlan plan(const ShaperDesign& design, const ExportOptions& options) {
  if (!is_c_identifier(options.c_name)) {
    throw InvalidArgument(fmt::format("--export-name = '{}' is not a C identifier; allowed: a letter or _ then letters, "
                                      "digits or _, at most 31 characters", options.c_name));
  }
  HeaderPlan h;
  h.taps = export_taps(design, options);
  h.bounds = c_header_bounds(h.taps);
  h.max_delay = sh::max_delay_samples(h.taps);
  h.history = std::bit_ceil(h.max_delay + 1);
  h.p = options.c_name;
  h.P = upper(h.p);
  h.fixed = h.bounds.q15.representable && h.bounds.q31.representable;
  return h;
}

// The worst residual vibration of the taps over 0.9 … 1.1 × the mode frequency.
double worst_band_residual(const sh::Shaper& discrete, double wn_rad_s, double zeta) {
  double worst = 0.0;
  for (std::size_t i = 0; i < kBandPoints; ++i) {
    const double r = kBandRatioLow + (kBandRatioHigh - kBandRatioLow) * static_cast<double>(i) / static_cast<double>(kBandPoints - 1);
    worst = std::max(worst, sh::residual_vibration(discrete, {r * wn_rad_s, zeta}));
  }
  return worst;
}

// The opening comment: the command, the design, the taps and their residual vibration.
std::string design_comment(const HeaderPlan& h, const ShaperDesign& design, const ExportOptions& options) {
  std::string s;
  s += fmt::format("/* {}.h: input shaper exported by clearshape {} (clearshape shape --export c-header).\n", h.p, kVersion);
  s += " * Generated file: regenerate rather than edit.\n";
  if (!design.command.empty()) s += fmt::format(" *   {}\n", design.command);
  s += " *\n";
  s += fmt::format(" * Design: {}", design.shaper.method());
  if (design.mode) {
    s += fmt::format(", mode {} Hz (wn = {} rad/s), zeta = {}", short_number(design.mode->natural_frequency_hz()),
                     short_number(design.mode->natural_frequency_rad_s), short_number(design.mode->damping_ratio));
  }
  if (design.second_mode) {
    s += fmt::format(", second mode {} Hz, zeta = {}", short_number(design.second_mode->natural_frequency_hz()),
                     short_number(design.second_mode->damping_ratio));
  }
  if (design.vtol) s += fmt::format(", Vtol = {}", short_number(*design.vtol));
  s += fmt::format(";\n *   {} impulses (time_s: amplitude):", design.shaper.size());
  for (const sh::Impulse& i : design.shaper.impulses()) s += fmt::format(" {}: {};", short_number(i.time_s), short_number(i.amplitude));
  if (design.update_grid_hz) {
    s += fmt::format("\n *   on the drive's {} Hz update grid (each impulse at the nearest update, those on one update merged).",
                     short_number(*design.update_grid_hz));
  }
  s += "\n *\n";
  s += fmt::format(" * Taps at Ts = {} s ({} discretisation): y[k] = sum_j w_j * u[k - d_j],\n",
                   shortest(options.sample_time_s),
                   options.discretization == sh::Discretization::linear ? "linear, first-order hold" : "exact at the mode");
  s += fmt::format(" *   N = {} taps, largest delay D = {} samples ({} s).\n", h.taps.size(), h.max_delay,
                   short_number(static_cast<double>(h.max_delay) * options.sample_time_s));
  if (design.mode) {
    const sh::Shaper discrete = taps_as_shaper(h.taps, options.sample_time_s);
    s += fmt::format(" * Residual vibration V (residual / unshaped residual; Singer & Seering 1990) at the design\n"
                     " *   mode: {:.3g} for the continuous shaper, {:.3g} for these taps; these taps over\n"
                     " *   0.9 .. 1.1 x the mode frequency: at most {:.3g}.\n",
                     sh::residual_vibration(design.shaper, *design.mode), sh::residual_vibration(discrete, *design.mode),
                     worst_band_residual(discrete, design.mode->natural_frequency_rad_s, design.mode->damping_ratio));
  }
  return s;
}

// The rest of the comment: number formats, error bounds (docs/export.md), use.
std::string formats_comment(const HeaderPlan& h) {
  std::string s = " *\n * Number formats\n";
  s += " *   double  w_j as the shortest decimal that reads back to the same IEEE-754 binary64. The double\n"
       " *           step repeats clearshape's StreamingShaper::step operation for operation, so with\n"
       " *           binary64 and no FMA contraction (-ffp-contract=off, GCC's default in ISO C modes) its\n"
       " *           output is bit for bit the C++ output.\n"
       " *           avr-gcc: double is 32-bit (the same as float) unless -mdouble=64; there the double\n"
       " *           shaper computes in binary32 and the float bound below applies to it.\n";
  s += " *   float   w_j rounded to the nearest binary32 (shortest round-trip literals).\n";
  if (h.fixed) {
    s += " *   Q15     int16_t q_j with value q_j / 2^15: q_j = round(w_j * 2^15), half away from zero, then\n"
         " *           corrected so that sum q_j = 32768 exactly (1.0: a step ends exactly at its target) -\n"
         " *           the taps rounded the wrong way the most move by one LSB. Signal int16_t, products\n"
         " *           and sum in int32_t (|sum| <= 2^30, no overflow: the taps are >= 0 and sum to 2^15),\n"
         " *           output (sum +/- 2^14) / 2^15: rounded half away from zero.\n";
    s += " *   Q31     the same with int32_t taps and signal, 2^31, int64_t sum (|sum| <= 2^62).\n";
  } else {
    s += fmt::format(" *   Q15/Q31 not generated: {}.\n", h.bounds.q15.why_not);
  }
  s += " *\n * Error bounds for an input with |x| <= X (y = exact sum_j w_j x_j; derived in\n"
       " * clearshape's docs/export.md):\n";
  // Two summation chains: γ_m with m = ceil(N/2) + 1 (Higham 2002, §3.1; c_header_bounds).
  s += fmt::format(" *   float   |y_float - y| <= X * {:.3e}   (sum|w_f - w| + gamma_m * sum|w_f|, m = {})\n",
                   h.bounds.float_gain_error, static_cast<int>(std::ceil(static_cast<double>(h.taps.size()) / 2.0) + 1));
  if (h.fixed) {
    s += fmt::format(" *   Q15     |y_q15 - y| <= 0.5 + X * {:.3e}   (0.5: output rounding; sum|q/2^15 - w|)\n",
                     h.bounds.q15.abs_error_sum);
    s += fmt::format(" *   Q31     |y_q31 - y| <= 0.5 + X * {:.3e}   (sum|q/2^31 - w|)\n", h.bounds.q31.abs_error_sum);
  }
  s += " *\n * Use, e.g. in a 1 kHz timer interrupt:\n";
  s += fmt::format(" *   static {0}_state_float shaper;            at start-up: {0}_reset_float(&shaper, position);\n"
                   " *   each tick: command = {0}_step_float(&shaper, command);\n"
                   " * Each state is one ring buffer of {1}_HISTORY samples (static storage, no allocation); a step\n"
                   " * is O({1}_TAPS) with no I/O. Use one state per axis.\n */\n",
                   h.p, h.P);
  return s;
}

// The include guard's opening, the sizes and the taps as macros.
std::string macros(const HeaderPlan& h, const ExportOptions& options) {
  const std::string& p = h.p;
  const std::string& P = h.P;
  std::vector<double> w;
  std::vector<std::size_t> d;
  for (const sh::DiscreteTap& t : h.taps) {
    w.push_back(t.weight);
    d.push_back(t.delay_samples);
  }
  std::string s = fmt::format("#ifndef {0}_H\n#define {0}_H\n\n#include <math.h>\n#include <stdint.h>\n\n", P);
  s += fmt::format("#define {}_SAMPLE_TIME_S {}\n", P, shortest(options.sample_time_s));
  s += fmt::format("#define {}_TAPS {}u\n", P, h.taps.size());
  s += fmt::format("#define {}_MAX_DELAY {}u\n", P, h.max_delay);
  s += fmt::format("#define {}_HISTORY {}u /* power of two > {}_MAX_DELAY */\n", P, h.history, P);
  s += fmt::format("#define {}_HAS_FIXED_POINT {}\n", P, h.fixed ? 1 : 0);
  const bool narrow = h.history <= 65536;
  s += fmt::format("typedef {} {}_index_t;\n", narrow ? "uint16_t" : "uint32_t", p);
  s += fmt::format("#define {0}_MASK (({1}_index_t)({0}_HISTORY - 1u))\n\n", P, p);
  s += fmt::format("#define {}_DELAYS {}\n", P, braced(d, [](std::size_t x) { return fmt::format("{}u", x); }));
  s += fmt::format("#define {}_TAPS_DOUBLE {}\n", P, braced(w, [](double x) { return shortest(x); }));
  s += fmt::format("#define {}_TAPS_FLOAT {}\n", P, braced(w, [](double x) { return shortest(static_cast<float>(x)) + "f"; }));
  if (h.fixed) {
    s += fmt::format("#define {}_TAPS_Q15 {}\n", P, braced(h.bounds.q15.q, [](std::int64_t q) { return fmt::format("{}", q); }));
    s += fmt::format("#define {}_TAPS_Q31 {}\n", P,
                     braced(h.bounds.q31.q, [](std::int64_t q) { return fmt::format("INT32_C({})", q); }));
  }
  return s + "\n";
}

// The state types and the reset/step functions of every format, and the guard's end.
std::string functions(const HeaderPlan& h) {
  const std::string& p = h.p;
  const std::string& P = h.P;
  std::string s;
  s += fmt::format("typedef struct {{ double history[{0}_HISTORY]; {1}_index_t head; }} {1}_state_double;\n", P, p);
  s += fmt::format("typedef struct {{ float history[{0}_HISTORY]; {1}_index_t head; }} {1}_state_float;\n", P, p);
  if (h.fixed) {
    s += fmt::format("typedef struct {{ int16_t history[{0}_HISTORY]; {1}_index_t head; }} {1}_state_q15;\n", P, p);
    s += fmt::format("typedef struct {{ int32_t history[{0}_HISTORY]; {1}_index_t head; }} {1}_state_q31;\n", P, p);
  }
  s += "\n";
  s += float_step(p, P, "double", P + "_TAPS_DOUBLE", "0.0");
  s += float_step(p, P, "float", P + "_TAPS_FLOAT", "0.0f");
  if (h.fixed) {
    s += fixed_step(p, P, "q15", "int16_t", "int32_t", P + "_TAPS_Q15", "INT32_C(16384)", "INT32_C(32768)");
    s += fixed_step(p, P, "q31", "int32_t", "int64_t", P + "_TAPS_Q31", "INT64_C(1073741824)", "INT64_C(2147483648)");
  }
  s += fmt::format("#endif /* {}_H */\n", P);
  return s;
}

}  // namespace

CHeaderBounds c_header_bounds(std::span<const sh::DiscreteTap> taps) {
  CHeaderBounds b;
  std::vector<double> w;
  double float_error = 0.0;
  double float_abs = 0.0;
  for (const sh::DiscreteTap& t : taps) {
    const auto wf = static_cast<float>(t.weight);
    float_error += std::abs(static_cast<double>(wf) - t.weight);
    float_abs += std::abs(static_cast<double>(wf));
    w.push_back(t.weight);
  }
  // Recursive summation on two chains: a term meets one product rounding, at most ceil(N/2) − 1
  // additions in its chain (0 + p is exact) and the final even + odd (Higham 2002, §3.1).
  const double m = std::ceil(static_cast<double>(taps.size()) / 2.0) + 1.0;
  const double u = std::ldexp(1.0, -24);
  b.float_gain_error = float_error + m * u / (1.0 - m * u) * float_abs;
  double sum = 0.0;
  for (double x : w) sum += x;
  if (std::abs(sum - 1.0) <= 1e-9) {
    b.q15 = quantize_taps(w, 15);
    b.q31 = quantize_taps(w, 31);
  } else {
    const std::string why = fmt::format("the taps sum to {} (not 1): fixed-point taps are scaled to sum 1.0", sum);
    b.q15.why_not = why;
    b.q31.why_not = why;
  }
  return b;
}

ExportText to_c_header(const ShaperDesign& design, const ExportOptions& options) {
  const HeaderPlan h = plan(design, options);
  ExportText out;
  out.text = design_comment(h, design, options) + formats_comment(h) + macros(h, options) + functions(h);
  if (!h.fixed) out.notes.push_back(fmt::format("c-header: no Q15/Q31 taps: {}", h.bounds.q15.why_not));
  return out;
}

}  // namespace clearshape::exports
