#include "clearshape/lti/process_model.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <limits>
#include <string>

#include "clearshape/core/error.hpp"

namespace clearshape::lti {

namespace {

constexpr std::array<std::string_view, 8> kAllNames = {"Kp", "Tp1", "Tp2", "Tp3", "Tw", "Zeta", "Td", "Tz"};

bool iequals(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
         });
}

[[noreturn]] void bad_code(std::string_view code, const std::string& problem) {
  throw InvalidArgument("process model structure \"" + std::string(code) + "\" is invalid: " + problem +
                        ". Allowed: \"P\" + pole count 0-3 + any of D (delay), Z (zero), U (underdamped "
                        "pair, needs 2 or 3 poles), I (integrator), e.g. \"P1D\", \"P2U\", \"P3UZ\".");
}

std::string list_names(const std::vector<std::string_view>& names) {
  std::string s;
  for (auto n : names) {
    if (!s.empty()) s += ", ";
    s += n;
  }
  return s;
}

// Sections of the cascade realization (input first).
StateSpace first_order_section(double tp) {  // 1/(1 + Tp s): ẋ = (u − x)/Tp, y = x
  StateSpace s;
  s.a = Eigen::MatrixXd::Constant(1, 1, -1.0 / tp);
  s.b = Eigen::MatrixXd::Constant(1, 1, 1.0 / tp);
  s.c = Eigen::MatrixXd::Constant(1, 1, 1.0);
  s.d = Eigen::MatrixXd::Zero(1, 1);
  return s;
}
StateSpace integrator_section() {  // 1/s
  StateSpace s;
  s.a = Eigen::MatrixXd::Zero(1, 1);
  s.b = Eigen::MatrixXd::Constant(1, 1, 1.0);
  s.c = Eigen::MatrixXd::Constant(1, 1, 1.0);
  s.d = Eigen::MatrixXd::Zero(1, 1);
  return s;
}
// 1/(1 + 2ζTw s + Tw² s²) with x1 = y, x2 = Tw·ẏ: ẋ1 = x2/Tw, ẋ2 = (u − x1 − 2ζ x2)/Tw.
StateSpace second_order_section(double tw, double zeta) {
  StateSpace s;
  s.a.resize(2, 2);
  s.a << 0.0, 1.0 / tw, -1.0 / tw, -2.0 * zeta / tw;
  s.b.resize(2, 1);
  s.b << 0.0, 1.0 / tw;
  s.c.resize(1, 2);
  s.c << 1.0, 0.0;
  s.d = Eigen::MatrixXd::Zero(1, 1);
  return s;
}

}  // namespace

// ---------------------------------------------------------------- ProcessStructure

ProcessStructure ProcessStructure::parse(std::string_view code) {
  if (code.size() < 2 || std::toupper(static_cast<unsigned char>(code[0])) != 'P') bad_code(code, "it must start with 'P' and a digit");
  ProcessStructure s;
  if (code[1] < '0' || code[1] > '3') bad_code(code, "the pole count must be 0, 1, 2 or 3");
  s.pole_count = code[1] - '0';
  for (std::size_t i = 2; i < code.size(); ++i) {
    bool* flag = nullptr;
    switch (std::toupper(static_cast<unsigned char>(code[i]))) {
      case 'D': flag = &s.delay; break;
      case 'Z': flag = &s.zero; break;
      case 'U': flag = &s.underdamped; break;
      case 'I': flag = &s.integrator; break;
      default: bad_code(code, std::string("unknown letter '") + code[i] + "'");
    }
    if (*flag) bad_code(code, std::string("letter '") + code[i] + "' appears twice");
    *flag = true;
  }
  if (s.underdamped && s.pole_count < 2) bad_code(code, "U (underdamped pair) needs 2 or 3 poles");
  if (s.zero && s.pole_count == 0 && !s.integrator) bad_code(code, "Z (zero) needs at least one pole or I, else the model is improper");
  return s;
}

std::string ProcessStructure::code() const {
  std::string c = "P";
  c += static_cast<char>('0' + pole_count);
  if (delay) c += 'D';
  if (integrator) c += 'I';
  if (zero) c += 'Z';
  if (underdamped) c += 'U';
  return c;
}

std::vector<std::string_view> ProcessStructure::parameter_names() const {
  std::vector<std::string_view> names{"Kp"};
  if (!underdamped) {
    for (int i = 0; i < pole_count; ++i) names.push_back(kAllNames[static_cast<std::size_t>(1 + i)]);
  } else if (pole_count == 3) {
    names.push_back("Tp3");
  }
  if (underdamped) {
    names.push_back("Tw");
    names.push_back("Zeta");
  }
  if (delay) names.push_back("Td");
  if (zero) names.push_back("Tz");
  return names;
}

bool ProcessStructure::has_parameter(std::string_view name) const {
  const auto names = parameter_names();
  return std::any_of(names.begin(), names.end(), [&](std::string_view n) { return iequals(n, name); });
}

// ---------------------------------------------------------------- ProcessParameters

namespace {
double* field(ProcessParameters& p, std::string_view name) {
  double* fields[] = {&p.kp, &p.tp1, &p.tp2, &p.tp3, &p.tw, &p.zeta, &p.td, &p.tz};
  for (std::size_t i = 0; i < kAllNames.size(); ++i)
    if (iequals(kAllNames[i], name)) return fields[i];
  throw InvalidArgument("process model parameter \"" + std::string(name) +
                        "\" is unknown; allowed: Kp, Tp1, Tp2, Tp3, Tw, Zeta, Td, Tz.");
}
}  // namespace

double ProcessParameters::get(std::string_view name) const {
  ProcessParameters copy = *this;
  return *field(copy, name);
}
void ProcessParameters::set(std::string_view name, double value) { *field(*this, name) = value; }

// ---------------------------------------------------------------- ProcessModel

ProcessModel::ProcessModel(std::string_view code, ProcessParameters parameters)
    : ProcessModel(ProcessStructure::parse(code), parameters) {}

ProcessModel::ProcessModel(ProcessStructure structure, ProcessParameters parameters)
    : structure_(structure), parameters_(parameters) {
  // Re-parse the canonical code to validate a hand-built structure.
  if (structure_.pole_count < 0 || structure_.pole_count > 3) {
    throw_invalid("process model pole_count", structure_.pole_count, "0, 1, 2 or 3");
  }
  (void)ProcessStructure::parse(structure_.code());
  const std::string remedy_unused = "This parameter is not part of structure " + structure_.code() +
                                    " (parameters: " + list_names(structure_.parameter_names()) +
                                    "); set it to 0 or choose a structure that has it.";
  for (std::string_view name : kAllNames) {
    const double value = parameters_.get(name);
    const std::string label = std::string(name) + " (" + structure_.code() + ")";
    if (!structure_.has_parameter(name)) {
      if (name != "Kp" && value != 0.0) throw_invalid(label, value, "0 (unused)", remedy_unused);
      continue;
    }
    if (name == "Kp" || name == "Tz") {
      require_finite(label, value);
    } else if (name == "Zeta") {
      require_non_negative(label, value, "Zeta is the damping ratio of the U pair; it cannot be negative (the model would be unstable).");
    } else if (name == "Td") {
      require_non_negative(label, value, "Td is a dead time in seconds.");
    } else {
      require_non_negative(label, value, "Time constants are in seconds and cannot be negative (procest models are stable); 0 removes the factor.");
    }
  }
  if (structure_.zero && parameters_.tz != 0.0) {
    const bool dynamic = structure_.integrator || parameters_.tp1 > 0.0 || parameters_.tp2 > 0.0 ||
                         parameters_.tp3 > 0.0 || parameters_.tw > 0.0;
    if (!dynamic) {
      throw_invalid("Tz (" + structure_.code() + ")", parameters_.tz, "0 when every time constant is 0",
                    "A zero without a pole is improper; give a positive time constant.");
    }
  }
}

ProcessModel ProcessModel::from_vector(ProcessStructure structure, std::span<const double> values) {
  const auto names = structure.parameter_names();
  if (values.size() != names.size()) {
    throw InvalidArgument("process model " + structure.code() + " takes " + std::to_string(names.size()) +
                          " parameters (" + list_names(names) + "), got " + std::to_string(values.size()) + ".");
  }
  ProcessParameters p;
  for (std::size_t i = 0; i < names.size(); ++i) p.set(names[i], values[i]);
  return ProcessModel(structure, p);
}

std::vector<double> ProcessModel::to_vector() const {
  std::vector<double> v;
  for (auto name : structure_.parameter_names()) v.push_back(parameters_.get(name));
  return v;
}

TransferFunction ProcessModel::transfer_function() const {
  const ProcessParameters& p = parameters_;
  Polynomial num = structure_.zero ? Polynomial{p.kp * p.tz, p.kp} : Polynomial{p.kp};  // Kp (1 + Tz s), Eq. 4.2
  Polynomial den{1.0};
  const double tps[] = {p.tp1, p.tp2, p.tp3};
  for (double tp : tps)
    if (tp > 0.0) den = multiply(den, {tp, 1.0});  // (1 + Tp s)
  if (structure_.underdamped && p.tw > 0.0) den = multiply(den, {p.tw * p.tw, 2.0 * p.zeta * p.tw, 1.0});  // Eq. 4.2
  if (structure_.integrator) den = multiply(den, {1.0, 0.0});
  return TransferFunction(std::move(num), std::move(den));
}

StateSpace ProcessModel::state_space() const {
  const ProcessParameters& p = parameters_;
  std::vector<StateSpace> sections;
  if (structure_.integrator) sections.push_back(integrator_section());
  const double tps[] = {p.tp1, p.tp2, p.tp3};
  for (double tp : tps)
    if (tp > 0.0) sections.push_back(first_order_section(tp));
  const bool pair = structure_.underdamped && p.tw > 0.0;
  if (pair) sections.push_back(second_order_section(p.tw, p.zeta));

  if (sections.empty()) {  // static gain (Tz = 0 by validation)
    StateSpace s;
    s.a.resize(0, 0);
    s.b.resize(0, 1);
    s.c.resize(1, 0);
    s.d = Eigen::MatrixXd::Constant(1, 1, p.kp);
    return s;
  }
  // Zero and gain go into the last section: y_last = Kp (x + Tz ẋ) of its output x.
  StateSpace& last = sections.back();
  const double tz = structure_.zero ? p.tz : 0.0;
  if (pair) {
    last.c(0, 1) = tz / p.tw;  // Tz ẏ = (Tz/Tw) x2
  } else if (last.a(0, 0) != 0.0) {  // first order: Tz ẋ = Tz (u − x)/Tp
    const double tp = -1.0 / last.a(0, 0);
    last.c(0, 0) = 1.0 - tz / tp;
    last.d(0, 0) = tz / tp;
  } else {  // integrator: Tz ẋ = Tz u
    last.d(0, 0) = tz;
  }
  last.c *= p.kp;
  last.d *= p.kp;
  StateSpace result = sections.front();
  for (std::size_t i = 1; i < sections.size(); ++i) result = series(result, sections[i]);
  return result;
}

std::vector<std::complex<double>> ProcessModel::poles() const {
  const ProcessParameters& p = parameters_;
  std::vector<std::complex<double>> r;
  const double tps[] = {p.tp1, p.tp2, p.tp3};
  for (double tp : tps)
    if (tp > 0.0) r.emplace_back(-1.0 / tp, 0.0);
  if (structure_.underdamped && p.tw > 0.0) {
    // Roots of Tw² s² + 2ζTw s + 1: s = (−ζ ± √(ζ² − 1))/Tw.
    const double z = p.zeta;
    if (z < 1.0) {
      const double wd = std::sqrt(1.0 - z * z) / p.tw;
      r.emplace_back(-z / p.tw, wd);
      r.emplace_back(-z / p.tw, -wd);
    } else {
      const double big = (-z - std::sqrt(z * z - 1.0)) / p.tw;
      r.emplace_back(big, 0.0);
      r.emplace_back(1.0 / (p.tw * p.tw * big), 0.0);  // product of the roots = 1/Tw²
    }
  }
  if (structure_.integrator) r.emplace_back(0.0, 0.0);
  std::sort(r.begin(), r.end(), [](const auto& x, const auto& y) {
    if (x.real() != y.real()) return x.real() < y.real();
    return x.imag() < y.imag();
  });
  return r;
}

std::vector<std::complex<double>> ProcessModel::zeros() const {
  if (structure_.zero && parameters_.tz != 0.0 && parameters_.kp != 0.0) return {{-1.0 / parameters_.tz, 0.0}};
  return {};
}

std::vector<OscillatoryMode> ProcessModel::oscillatory_modes() const {
  const auto p = poles();
  return lti::oscillatory_modes(p);
}

double ProcessModel::dc_gain() const noexcept {
  if (!structure_.integrator || parameters_.kp == 0.0) return parameters_.kp;
  return std::copysign(std::numeric_limits<double>::infinity(), parameters_.kp);
}

std::complex<double> ProcessModel::frequency_response(double frequency_rad_s) const noexcept {
  const ProcessParameters& p = parameters_;
  const std::complex<double> s(0.0, frequency_rad_s);
  std::complex<double> g = p.kp;
  if (structure_.zero) g *= 1.0 + p.tz * s;
  const double tps[] = {p.tp1, p.tp2, p.tp3};
  for (double tp : tps) g /= 1.0 + tp * s;
  if (structure_.underdamped) g /= 1.0 + 2.0 * p.zeta * p.tw * s + p.tw * p.tw * s * s;  // Eq. 4.2
  if (structure_.integrator) g /= s;
  if (structure_.delay) g *= std::exp(-p.td * s);
  return g;
}

double ProcessModel::natural_frequency_rad_s() const {
  if (!structure_.underdamped) {
    throw InvalidArgument("natural frequency: process model " + structure_.code() +
                          " has no underdamped pair (U); use oscillatory_modes() or a U structure such as P3UZ.");
  }
  require_positive("Tw (" + structure_.code() + ")", parameters_.tw, "ωn = 1/Tw needs Tw > 0.");
  return 1.0 / parameters_.tw;  // thesis §4.2: ωn = 1/Tw
}

double ProcessModel::damping_ratio() const {
  if (!structure_.underdamped) {
    throw InvalidArgument("damping ratio: process model " + structure_.code() +
                          " has no underdamped pair (U); use oscillatory_modes() or a U structure such as P3UZ.");
  }
  return parameters_.zeta;  // thesis §4.2: ξ = Zeta
}

ProcessModel thesis_speed_mode_model() {
  ProcessParameters p;  // thesis Eq. 4.2, speed operation mode
  p.kp = 25.47;
  p.tz = -0.0398;
  p.zeta = 0.2880;
  p.tw = 0.0479;
  p.tp3 = 0.0857;
  return ProcessModel("P3UZ", p);
}

ProcessModel thesis_position_mode_model() {
  ProcessParameters p;  // thesis Eq. 4.2, position operation mode
  p.kp = 0.9959;
  p.tz = 0.0042;
  p.zeta = 0.9968;
  p.tw = 0.0102;
  p.tp3 = 0.0034;
  return ProcessModel("P3UZ", p);
}

}  // namespace clearshape::lti
