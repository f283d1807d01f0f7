// --export c-header, compiled and run: the generated header is built with the system C compiler
// (cc -std=c99 -Wall -Wextra -Werror -pedantic) and with avr-gcc for an ATmega2560, and its
// streaming shapers run on the committed command signals (tests/golden/apply_input.csv: step,
// ramp, PRBS, sine). Double: bit for bit the C++ StreamingShaper. Float, Q15, Q31: within the
// bounds the header states (c_header.hpp; derived in docs/export.md) — and not trivially. The
// ZVD header also runs on an ATmega2560 in simavr: Q15/Q31 equal to the host, binary32 in bound.
#include <unistd.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "clearshape/core/error.hpp"
#include "clearshape/export/c_header.hpp"
#include "clearshape/export/numbers.hpp"
#include "clearshape/io/table.hpp"
#include "clearshape/shaping/design.hpp"
#include "clearshape/shaping/streaming.hpp"
#include "support/paths.hpp"

namespace ex = clearshape::exports;
namespace sh = clearshape::shaping;
namespace fs = std::filesystem;

namespace {

fs::path temp_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("clearshape_export_c_" + std::to_string(::getpid()) + "_" + name);
  fs::create_directories(dir);
  return dir;
}

void write_file(const fs::path& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
}

std::string read_file(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Runs a shell command; returns its exit status and puts stdout+stderr in `output`.
int run(const std::string& command, std::string& output) {
  const fs::path log = fs::temp_directory_path() / ("clearshape_export_c_log_" + std::to_string(::getpid()));
  const int status = std::system((command + " >" + log.string() + " 2>&1").c_str());
  output = read_file(log);
  fs::remove(log);
  return status;
}

bool have(const std::string& tool) {
  std::string ignored;
  return run("command -v " + tool, ignored) == 0;
}

// The driver: reads a CSV with the header "u,x15,x31" (the first row also resets every state), prints
// "y_double y_float y_q15 y_q31" with %a (exact) for the floating-point outputs.
std::string driver(const std::string& p) {
  std::string c = R"(#include <stdio.h>
#include <stdlib.h>
#include "shaper.h"
int main(int argc, char **argv)
{
  static P_state_double sd;
  static P_state_float sf;
#if PP_HAS_FIXED_POINT
  static P_state_q15 s15;
  static P_state_q31 s31;
#endif
  char line[256];
  int first = 1;
  int header = 1;
  FILE *in;
  FILE *out;
  if (argc != 3) return 2;
  in = fopen(argv[1], "r");
  out = fopen(argv[2], "w");
  if (in == NULL || out == NULL) return 2;
  while (fgets(line, sizeof line, in) != NULL) {
    char *end;
    double u;
    long x15;
    long x31;
    if (header) {
      header = 0;
      continue;
    }
    u = strtod(line, &end);
    x15 = strtol(end + 1, &end, 10);
    x31 = strtol(end + 1, &end, 10);
    if (first) {
      P_reset_double(&sd, u);
      P_reset_float(&sf, (float)u);
#if PP_HAS_FIXED_POINT
      P_reset_q15(&s15, (int16_t)x15);
      P_reset_q31(&s31, (int32_t)x31);
#endif
      first = 0;
    }
    fprintf(out, "%a %a", P_step_double(&sd, u), (double)P_step_float(&sf, (float)u));
#if PP_HAS_FIXED_POINT
    fprintf(out, " %d %ld\n", (int)P_step_q15(&s15, (int16_t)x15), (long)P_step_q31(&s31, (int32_t)x31));
#else
    fprintf(out, " 0 0\n");
    (void)x15;
    (void)x31;
#endif
  }
  fclose(in);
  return fclose(out) == 0 ? 0 : 1;
}
)";
  std::string upper = p;
  for (char& ch : upper) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  std::string out;
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (c.compare(i, 3, "PP_") == 0) {
      out += upper + "_";
      i += 2;
    } else if (c.compare(i, 2, "P_") == 0 && (i == 0 || !std::isalnum(static_cast<unsigned char>(c[i - 1])))) {
      out += p + "_";
      i += 1;
    } else {
      out += c[i];
    }
  }
  return out;
}

// The committed command signals, one after the other, with one NaN (held by both sides).
std::vector<double> command_signal() {
  const clearshape::io::Table t = clearshape::io::read_table(clearshape::testing::golden_path("apply_input.csv"));
  std::vector<double> u;
  for (const char* name : {"step", "ramp", "prbs", "sine"}) {
    for (double x : t.column(name)) u.push_back(x);
  }
  u[500] = std::numeric_limits<double>::quiet_NaN();
  return u;
}

double max_abs_finite(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) {
    if (std::isfinite(x)) m = std::max(m, std::abs(x));
  }
  return m;
}

std::vector<double> stream(std::span<const sh::DiscreteTap> taps, double ts, const std::vector<double>& u) {
  sh::StreamingShaper s(taps, ts, u.front());
  std::vector<double> y;
  for (double x : u) y.push_back(s.step(x));
  return y;
}

// One non-static wrapper per step function, so that every one is emitted into the object.
std::string wrappers(const std::string& p, bool fixed) {
  std::string c = "#include \"shaper.h\"\n";
  c += "double run_double(double x);\nfloat run_float(float x);\n";
  c += "double run_double(double x) { static P_state_double s; return P_step_double(&s, x); }\n";
  c += "float run_float(float x) { static P_state_float s; return P_step_float(&s, x); }\n";
  if (fixed) {
    c += "int16_t run_q15(int16_t x);\nint32_t run_q31(int32_t x);\n";
    c += "int16_t run_q15(int16_t x) { static P_state_q15 s; P_reset_q15(&s, 0); return P_step_q15(&s, x); }\n";
    c += "int32_t run_q31(int32_t x) { static P_state_q31 s; P_reset_q31(&s, 0); return P_step_q31(&s, x); }\n";
  }
  std::string out;
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (c.compare(i, 2, "P_") == 0) {
      out += p + "_";
      ++i;
    } else {
      out += c[i];
    }
  }
  return out;
}

struct Case {
  std::string name;
  ex::ShaperDesign design;
  ex::ExportOptions options;
  bool avr = false;  ///< also run the header on an ATmega2560 in simavr
};

// An ATmega2560 program (simavr's console on GPIOR0) that runs the four shapers on inputs held
// in flash and prints each output's 32 bits in hex, one line per sample.
std::string avr_program(const std::vector<double>& u, const std::vector<double>& x15, const std::vector<double>& x31) {
  std::string c = "#include <avr/interrupt.h>\n#include <avr/io.h>\n#include <avr/pgmspace.h>\n#include <avr/sleep.h>\n"
                  "#include <math.h>\n#include \"avr/avr_mcu_section.h\"\n#include \"shaper.h\"\n"
                  "AVR_MCU(16000000, \"atmega2560\");\nAVR_MCU_SIMAVR_CONSOLE(&GPIOR0);\n";
  auto list = [&c](const char* decl, const std::vector<double>& v, auto format) {
    c += decl;
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (i > 0) c += ',';
      c += format(v[i]);
    }
    c += "};\n";
  };
  char buf[64];
  list("static const float in_f[] PROGMEM = {", u, [](double x) {
    return std::isfinite(x) ? ex::shortest(static_cast<float>(x)) + "f" : std::string("NAN");
  });
  list("static const int16_t in_15[] PROGMEM = {", x15, [&buf](double x) {
    std::snprintf(buf, sizeof buf, "%.0f", x);
    return std::string(buf);
  });
  list("static const int32_t in_31[] PROGMEM = {", x31, [&buf](double x) {
    std::snprintf(buf, sizeof buf, "INT32_C(%.0f)", x);
    return std::string(buf);
  });
  c += R"(static void put(char c) { GPIOR0 = (uint8_t)c; }
static void hex32(uint32_t v)
{
  int i;
  for (i = 7; i >= 0; --i) {
    uint8_t d = (uint8_t)((v >> (4 * i)) & 0xFu);
    put((char)(d < 10 ? '0' + d : 'a' + d - 10));
  }
}
int main(void)
{
  static cs_shaper_state_double sd;
  static cs_shaper_state_float sf;
  static cs_shaper_state_q15 s15;
  static cs_shaper_state_q31 s31;
  unsigned i;
  cs_shaper_reset_double(&sd, pgm_read_float(&in_f[0]));
  cs_shaper_reset_float(&sf, pgm_read_float(&in_f[0]));
  cs_shaper_reset_q15(&s15, (int16_t)pgm_read_word(&in_15[0]));
  cs_shaper_reset_q31(&s31, (int32_t)pgm_read_dword(&in_31[0]));
  for (i = 0; i < sizeof in_f / sizeof in_f[0]; ++i) {
    union { float f; uint32_t u; } a, b;
    float x = pgm_read_float(&in_f[i]);
    a.f = (float)cs_shaper_step_double(&sd, x);
    b.f = cs_shaper_step_float(&sf, x);
    hex32(a.u);
    put(' ');
    hex32(b.u);
    put(' ');
    hex32((uint32_t)(int32_t)cs_shaper_step_q15(&s15, (int16_t)pgm_read_word(&in_15[i])));
    put(' ');
    hex32((uint32_t)cs_shaper_step_q31(&s31, (int32_t)pgm_read_dword(&in_31[i])));
    put('\r'); /* simavr prints the console line on a carriage return */
  }
  cli();
  sleep_cpu(); /* simavr ends the run: sleeping with interrupts off */
  return 0;
}
)";
  return c;
}

float float_from_bits(std::uint32_t bits) {
  float f = 0.0f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

ex::ShaperDesign designed(sh::Method m, double f_hz, double zeta) {
  sh::DesignRequest r;
  r.method = m;
  r.mode = sh::Mode::from_hz(f_hz, zeta);
  return {sh::design(r), m, r.mode, std::nullopt, std::nullopt, std::nullopt, ""};
}

void run_case(const Case& c) {
  SCOPED_TRACE(c.name);
  const fs::path dir = temp_dir(c.name);
  const ex::ExportText header = ex::to_c_header(c.design, c.options);
  write_file(dir / "shaper.h", header.text);
  write_file(dir / "driver.c", driver(c.options.c_name));
  std::string log;
  ASSERT_EQ(run("cc -std=c99 -Wall -Wextra -Werror -pedantic -O2 -o " + (dir / "driver").string() + " " +
                    (dir / "driver.c").string() + " -lm",
                log),
            0)
      << log;

  const std::vector<sh::DiscreteTap> taps = ex::export_taps(c.design, c.options);
  const ex::CHeaderBounds bounds = ex::c_header_bounds(taps);
  const std::vector<double> u = command_signal();
  const double x_max = max_abs_finite(u);
  const double s15 = 30000.0 / x_max;
  const double s31 = 2.0e9 / x_max;
  std::vector<double> uf;   // the float driver's input, as the C++ reference sees it
  std::vector<double> x15;  // integer inputs (the NaN sample holds the previous value)
  std::vector<double> x31;
  std::string input = "u,x15,x31\n";
  char buffer[128];
  for (std::size_t k = 0; k < u.size(); ++k) {
    const double held = std::isfinite(u[k]) ? u[k] : u[k - 1];
    uf.push_back(static_cast<double>(static_cast<float>(u[k])));
    x15.push_back(std::round(held * s15));
    x31.push_back(std::round(held * s31));
    std::snprintf(buffer, sizeof buffer, "%.17g,%.0f,%.0f\n", u[k], x15.back(), x31.back());
    input += buffer;
  }
  write_file(dir / "in.csv", input);
  ASSERT_EQ(run((dir / "driver").string() + " " + (dir / "in.csv").string() + " " + (dir / "out.txt").string(), log), 0)
      << log;

  const std::vector<double> ref_d = stream(taps, c.options.sample_time_s, u);
  const std::vector<double> ref_f = stream(taps, c.options.sample_time_s, uf);
  const std::vector<double> ref_15 = stream(taps, c.options.sample_time_s, x15);
  const std::vector<double> ref_31 = stream(taps, c.options.sample_time_s, x31);
  // Rounding of the binary64 reference itself (same chain length, u = 2^-53), for the bounds.
  const double m = std::ceil(static_cast<double>(taps.size()) / 2.0) + 1.0;
  const double gamma64 = m * std::ldexp(1.0, -53) / (1.0 - m * std::ldexp(1.0, -53));
  double sum_abs_w = 0.0;
  for (const auto& t : taps) sum_abs_w += std::abs(t.weight);

  const double xf = max_abs_finite(uf);
  const double bound_f = xf * (bounds.float_gain_error + gamma64 * sum_abs_w);
  const double bound_15 = 0.5 + 30000.0 * bounds.q15.abs_error_sum + 30000.0 * gamma64 * sum_abs_w;
  const double bound_31 = 0.5 + 2.0e9 * bounds.q31.abs_error_sum + 2.0e9 * gamma64 * sum_abs_w;
  std::istringstream out(read_file(dir / "out.txt"));
  std::size_t k = 0;
  std::size_t bit_equal = 0;
  std::vector<double> host_f;
  std::vector<long> host_15;
  std::vector<long> host_31;
  double worst_f = 0.0;
  double worst_15 = 0.0;
  double worst_31 = 0.0;
  for (std::string a, b, q15, q31; out >> a >> b >> q15 >> q31; ++k) {
    ASSERT_LT(k, u.size());
    const double yd = std::strtod(a.c_str(), nullptr);
    const double yf = std::strtod(b.c_str(), nullptr);
    host_f.push_back(yf);
    host_15.push_back(std::stol(q15));
    host_31.push_back(std::stol(q31));
    if (yd == ref_d[k] && std::signbit(yd) == std::signbit(ref_d[k])) ++bit_equal;
    worst_f = std::max(worst_f, std::abs(yf - ref_f[k]));
    if (bounds.q15.representable) {
      worst_15 = std::max(worst_15, std::abs(std::stod(q15) - ref_15[k]));
      worst_31 = std::max(worst_31, std::abs(std::stod(q31) - ref_31[k]));
    }
  }
  ASSERT_EQ(k, u.size());
  EXPECT_EQ(bit_equal, u.size()) << "double: C and C++ differ in " << u.size() - bit_equal << " samples";
  EXPECT_LE(worst_f, bound_f);
  EXPECT_GT(worst_f, 0.0);  // float really is a different arithmetic: the comparison is not vacuous
  std::printf("[%s] taps %zu: double bit-equal %zu/%zu; float max err %.3g (bound %.3g)", c.name.c_str(), taps.size(),
              bit_equal, u.size(), worst_f, bound_f);
  if (bounds.q15.representable) {
    EXPECT_LE(worst_15, bound_15);
    EXPECT_LE(worst_31, bound_31);
    EXPECT_GT(worst_15, 0.0);
    std::printf("; Q15 %.3g LSB (bound %.3g); Q31 %.3g LSB (bound %.3g)", worst_15, bound_15, worst_31, bound_31);
  }
  std::printf("\n");

  if (c.avr) {
    // The same header on an ATmega2560 (avr-gcc: double is binary32) in simavr: integer outputs
    // equal the host's exactly, binary32 outputs stay within the float bound.
    const char* mcu_section = "/usr/include/simavr/avr/avr_mcu_section.h";
    ASSERT_TRUE(fs::exists(mcu_section) && have("avr-gcc") && have("simavr"))
        << "avr-gcc, avr-libc, simavr and libsimavr-dev are needed (scripts/install-deps.sh)";
    write_file(dir / "avr.c", avr_program(u, x15, x31));
    ASSERT_EQ(run("avr-gcc -mmcu=atmega2560 -std=c99 -Os -Wall -Wextra -Werror -pedantic -idirafter /usr/include/simavr "
                  "-Wl,--undefined=_mmcu,--section-start=.mmcu=0x910000 -o " + (dir / "avr.elf").string() + " " +
                      (dir / "avr.c").string(),
                  log),
              0)
        << log.substr(0, 2000);
    ASSERT_EQ(run("timeout 60 simavr " + (dir / "avr.elf").string(), log), 0) << log;
    std::istringstream lines(log);
    std::size_t n = 0;
    std::size_t float_equal_host = 0;
    double worst_avr = 0.0;
    for (std::string line; std::getline(lines, line);) {
      const std::size_t at = line.find("O:");
      if (at == std::string::npos) continue;
      std::istringstream fields(line.substr(at + 2));
      std::string hd, hf, h15, h31;
      fields >> hd >> hf >> h15 >> h31;
      ASSERT_LT(n, u.size());
      const float yd = float_from_bits(static_cast<std::uint32_t>(std::stoul(hd, nullptr, 16)));
      const float yf = float_from_bits(static_cast<std::uint32_t>(std::stoul(hf, nullptr, 16)));
      EXPECT_EQ(std::memcmp(&yd, &yf, sizeof yd), 0) << "sample " << n << ": the AVR's double is its float";
      worst_avr = std::max(worst_avr, std::abs(static_cast<double>(yf) - ref_f[n]));
      if (static_cast<double>(yf) == host_f[n]) ++float_equal_host;
      if (bounds.q15.representable) {
        EXPECT_EQ(static_cast<std::int16_t>(std::stoul(h15, nullptr, 16)), host_15[n]) << "Q15 sample " << n;
        EXPECT_EQ(static_cast<std::int32_t>(std::stoul(h31, nullptr, 16)), host_31[n]) << "Q31 sample " << n;
      }
      ++n;
    }
    ASSERT_EQ(n, u.size()) << log.substr(0, 500);
    EXPECT_LE(worst_avr, bound_f);
    std::printf("[%s] ATmega2560 (simavr): float max err %.3g (bound %.3g), %zu/%zu float outputs equal the host's; "
                "Q15/Q31 equal the host's\n", c.name.c_str(), worst_avr, bound_f, float_equal_host, n);
  }
  fs::remove_all(dir);
}

}  // namespace

TEST(CHeader, ZvdOnTheHostBitForBitAndOnAnAtmega2560) {
  Case c{"zvd", designed(sh::Method::zvd, 13.7, 0.07), {}};
  c.options.sample_time_s = 1e-3;
  c.avr = true;
  run_case(c);
}

TEST(CHeader, Ei3ExactDiscretisationEvenTapCount) {
  Case c{"ei3", designed(sh::Method::ei3, 7.3, 0.05), {}};
  c.design.vtol = 0.05;
  c.options.sample_time_s = 2e-3;
  c.options.discretization = sh::Discretization::exact_at_mode;
  c.options.c_name = "axis_x";
  run_case(c);
}

TEST(CHeader, NegativeShaperHasNoFixedPoint) {
  Case c{"umzv", designed(sh::Method::um_zv, 9.1, 0.02), {}};
  c.options.sample_time_s = 1e-3;
  const ex::ExportText h = ex::to_c_header(c.design, c.options);
  EXPECT_NE(h.text.find("#define CS_SHAPER_HAS_FIXED_POINT 0"), std::string::npos);
  EXPECT_EQ(h.text.find("step_q15"), std::string::npos);
  ASSERT_EQ(h.notes.size(), 1u);
  EXPECT_NE(h.notes[0].find("negative"), std::string::npos);
  run_case(c);
}

TEST(CHeader, CompilesForAvrAndUsesNoLibrary) {
  ASSERT_TRUE(have("avr-gcc")) << "avr-gcc missing: scripts/install-deps.sh installs gcc-avr and avr-libc";
  ex::ExportOptions o;
  o.sample_time_s = 1e-3;
  const fs::path dir = temp_dir("avr");
  write_file(dir / "shaper.h", ex::to_c_header(designed(sh::Method::zvdd, 4.0, 0.1), o).text);
  write_file(dir / "use.c", wrappers("cs_shaper", true));
  const std::string flags = " -std=c99 -Wall -Wextra -Werror -pedantic -c -o ";
  std::string log;
  ASSERT_EQ(run("avr-gcc -mmcu=atmega2560 -Os" + flags + (dir / "avr.o").string() + " " + (dir / "use.c").string(), log), 0)
      << log;
  ASSERT_EQ(run("cc -O2" + flags + (dir / "host.o").string() + " " + (dir / "use.c").string(), log), 0) << log;
  // Undefined symbols: only the compiler's own arithmetic helpers (__mulsi3, __divdi3, …) —
  // no malloc, no I/O, no libm.
  for (const auto& [nm, obj] : {std::pair{"avr-nm", "avr.o"}, std::pair{"nm", "host.o"}}) {
    ASSERT_EQ(run(std::string(nm) + " -u " + (dir / obj).string(), log), 0) << log;
    std::istringstream in(log);
    for (std::string kind, name; in >> kind >> name;) {
      EXPECT_EQ(name.rfind("__", 0), 0u) << obj << " needs " << name;
    }
  }
  fs::remove_all(dir);
}

TEST(CHeader, LongShaperUsesWideIndicesAndOneTapCompiles) {
  ex::ExportOptions o;
  o.sample_time_s = 1e-6;  // the thesis's 3.32 Hz mode at 1 MHz: ~3e5 samples of history
  const ex::ExportText wide = ex::to_c_header(designed(sh::Method::zvd, 3.32, 0.288), o);
  EXPECT_NE(wide.text.find("typedef uint32_t cs_shaper_index_t;"), std::string::npos);
  ex::ShaperDesign identity{sh::Shaper("custom", {{0.0, 1.0}}), sh::Method::custom, {}, {}, {}, {}, ""};
  o.sample_time_s = 1e-3;
  o.c_name = "one";
  const ex::ExportText one = ex::to_c_header(identity, o);
  EXPECT_NE(one.text.find("#define ONE_TAPS 1u"), std::string::npos);
  const fs::path dir = temp_dir("shapes");
  std::string log;
  for (const auto& [name, prefix, text] :
       {std::tuple{"wide", "cs_shaper", wide.text}, std::tuple{"one", "one", one.text}}) {
    write_file(dir / "shaper.h", text);
    write_file(dir / "use.c", wrappers(prefix, std::string(name) == "wide"));
    EXPECT_EQ(run("cc -std=c99 -Wall -Wextra -Werror -pedantic -c -o " + (dir / "u.o").string() + " " +
                      (dir / "use.c").string(),
                  log),
              0)
        << name << ": " << log;
  }
  ex::ExportOptions bad = o;
  bad.c_name = "9lives";
  EXPECT_THROW(ex::to_c_header(identity, bad), clearshape::InvalidArgument);
  fs::remove_all(dir);
}
