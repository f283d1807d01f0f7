// The study report renders: python/render_study.py draws every figure of a study output folder
// (PNG + PDF, same bytes for the same inputs) and writes a self-contained report.html, which
// headless Chromium opens offline with every figure decoded (data-figures-loaded == number of
// <img>, data-figures-failed == 0); a corrupted figure is detected. Issue 13's and issue 22's defects
// each have a check in tests/report/report_checks.py, run here on the rendered report; the page is laid out
// at 1400 px and printed to PDF by python/report_shots.py. The study output is the
// quick thesis-position study when `clearshape study` exists, else a synthetic fixture
// (python/clearshape_plot/fixture.py).
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/cli.hpp"
#include "support/paths.hpp"
#include "support/shared_fixture.hpp"

namespace fs = std::filesystem;

namespace {

struct Shell {
  int exit_code = -1;
  std::string out;
};

/// Runs a shell command, stdout and stderr together.
Shell run(const std::string& command) {
  Shell r;
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return r;
  std::array<char, 4096> buffer{};
  std::size_t n = 0;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) r.out.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

std::string quote(const fs::path& p) {  // appended, not "'" + …: GCC 12 -Wrestrict false positive
  std::string quoted = "'";
  quoted += p.string();
  quoted += '\'';
  return quoted;
}

fs::path repo_root() { return fs::path(CLEARSHAPE_GOLDEN_DIR).parent_path().parent_path(); }

fs::path python_dir() { return repo_root() / "python"; }

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool have_chromium() { return run("command -v chromium").exit_code == 0; }

/// Writes the synthetic fixture into `dir`.
void write_fixture(const fs::path& dir) {
  const Shell r = run("cd " + quote(python_dir()) + " && /usr/bin/python3 -m clearshape_plot.fixture " + quote(dir));
  ASSERT_EQ(r.exit_code, 0) << r.out;
}

Shell render(const fs::path& dir) {
  return run("/usr/bin/python3 " + quote(python_dir() / "render_study.py") + " " + quote(dir));
}

/// Opens the report in headless Chromium, returns the serialized DOM after 5 s of virtual time.
Shell dump_dom(const fs::path& report, const fs::path& profile) {
  return run("timeout 180 chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run "
             "--disable-background-networking --disable-component-update --disable-sync --user-data-dir=" +
             quote(profile) + " --virtual-time-budget=5000 --dump-dom " + quote("file://" + report.string()) +
             " 2>/dev/null");
}

/// Value of attribute `name` on the dumped <body>, or "" when it is absent.
std::string body_attribute(const std::string& dom, const std::string& name) {
  std::smatch body;
  if (!std::regex_search(dom, body, std::regex("<body[^>]*>"))) return "";
  const std::string tag = body.str();
  std::smatch m;
  if (!std::regex_search(tag, m, std::regex(name + "=\"([^\"]*)\""))) return "";
  return m[1].str();
}

std::size_t count(const std::string& text, const std::string& needle) {
  std::size_t n = 0;
  for (auto pos = text.find(needle); pos != std::string::npos; pos = text.find(needle, pos + 1)) ++n;
  return n;
}

class Report : public ::testing::Test {
 protected:
  // The quick study and its render are built once per build tree (support/shared_fixture.hpp)
  // and read by every test process of the suite; base_ is this process's scratch folder.
  static void SetUpTestSuite() {
    base_ = fs::temp_directory_path() / ("clearshape_report_" + std::to_string(::getpid()));
    fs::remove_all(base_);
    fs::create_directories(base_);
    const fs::path protocol = repo_root() / "studies" / "thesis-position.toml";
    const std::string key = clearshape::testing::files_key({CLEARSHAPE_CLI, python_dir(), protocol});
    const fs::path fixture = clearshape::testing::shared_fixture("report-quick-study", key, [&](const fs::path& dir) {
      return build_fixture(dir, protocol);
    });
    if (fixture.empty()) {
      setup_error_ = "the report fixture could not be built (see the first test's output)";
      return;
    }
    study_ = fixture / "study";
    source_ = read_file(fixture / "source.txt");
    render_.exit_code = std::stoi(read_file(fixture / "render_exit.txt"));
    render_.out = read_file(fixture / "render_out.txt");
    std::fprintf(stderr, "report test: study output from the %s\n", source_.c_str());
  }
  // The quick thesis-position study (or, when the study cannot run, the synthetic fixture) and
  // its render into `dir`: study/, source.txt, render_exit.txt, render_out.txt.
  static bool build_fixture(const fs::path& dir, const fs::path& protocol) {
    const fs::path study = dir / "study";
    std::string source;
    const auto help = clearshape::testing::run_cli("study --help");
    bool have_study = false;
    if (help.exit_code == 0 && fs::exists(protocol)) {
      const auto r = clearshape::testing::run_cli("study " + quote(protocol) + " --quick --out " + quote(study));
      have_study = r.exit_code == 0;
      source = "quick thesis-position study";
      if (!have_study) {  // the study's own tests report its failures; this suite tests the report
        std::fprintf(stderr, "clearshape study --quick failed (exit %d), using the synthetic fixture:\n%s\n",
                     r.exit_code, r.err.c_str());
        fs::remove_all(study);
      }
    }
    if (!have_study) {
      source = "synthetic fixture (python/clearshape_plot/fixture.py)";
      const Shell r = run("cd " + quote(python_dir()) + " && /usr/bin/python3 -m clearshape_plot.fixture " + quote(study));
      if (r.exit_code != 0) {
        std::fprintf(stderr, "fixture failed:\n%s\n", r.out.c_str());
        return false;
      }
    }
    const Shell rendered = render(study);
    std::ofstream(dir / "source.txt", std::ios::binary) << source;
    std::ofstream(dir / "render_exit.txt", std::ios::binary) << rendered.exit_code;
    std::ofstream(dir / "render_out.txt", std::ios::binary) << rendered.out;
    return true;
  }
  void SetUp() override {
    ASSERT_TRUE(setup_error_.empty()) << setup_error_;
    RecordProperty("study_source", source_);
  }

  /// Entries of figures.json (the report may add its own summary figure on top).
  static std::size_t figure_entries() {
    const auto index = nlohmann::json::parse(read_file(study_ / "figures.json"));
    return index.at("figures").size();
  }
  /// Figures the report says it embeds (data-figures-expected on <body>).
  static std::size_t figures_expected(const std::string& html) {
    std::smatch m;
    if (!std::regex_search(html, m, std::regex("data-figures-expected=\"([0-9]+)\""))) return 0;
    return std::stoul(m[1].str());
  }

  static inline fs::path base_;
  static inline fs::path study_;
  static inline std::string source_;
  static inline std::string setup_error_;
  static inline Shell render_;
};

TEST_F(Report, RenderDrawsEveryFigureAsPngAndPdf) {
  ASSERT_EQ(render_.exit_code, 0) << source_ << "\n" << render_.out;
  EXPECT_NE(render_.out.find("report.html"), std::string::npos) << "prints where the report is:\n" << render_.out;
  const std::size_t n = figures_expected(read_file(study_ / "report.html"));
  ASSERT_GT(figure_entries(), 0U) << "figures.json lists no figure";
  EXPECT_GE(n, figure_entries());
  std::size_t png = 0;
  for (const auto& e : fs::directory_iterator(study_ / "figures")) {
    if (e.path().extension() != ".png") continue;
    ++png;
    const std::string bytes = read_file(e.path());
    EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << e.path();
    fs::path pdf = e.path();
    pdf.replace_extension(".pdf");
    ASSERT_TRUE(fs::exists(pdf)) << pdf;
    EXPECT_EQ(read_file(pdf).substr(0, 5), "%PDF-") << pdf;
  }
  EXPECT_EQ(png, n);
}

TEST_F(Report, SelfContainedInThesisOrder) {
  const std::string html = read_file(study_ / "report.html");
  ASSERT_FALSE(html.empty());
  // Every figure embedded, nothing fetched: no external src/href/url(), no <link>.
  EXPECT_EQ(count(html, "<img "), figures_expected(html));
  EXPECT_GE(count(html, "<img "), figure_entries());
  EXPECT_EQ(count(html, "<img "), count(html, "src=\"data:image/png;base64,"));
  EXPECT_EQ(count(html, "src=\"http"), 0U);
  EXPECT_EQ(count(html, "<link"), 0U);
  EXPECT_EQ(count(html, "url("), 0U);
  // Table of contents and sections in the thesis's order.
  std::size_t last = 0;
  for (const char* id : {"setup", "consistency", "identification", "clearance", "simulated", "rig",
                         "ambiguities", "differences"}) {
    const auto pos = html.find(std::string("<section id=\"") + id + "\"");
    ASSERT_NE(pos, std::string::npos) << id;
    EXPECT_GT(pos, last) << id << " out of order";
    last = pos;
    EXPECT_NE(html.find(std::string("href=\"#") + id + "\""), std::string::npos) << "TOC lacks " << id;
  }
  // Numbers beside the thesis's with a difference column, and verdicts.
  EXPECT_NE(html.find(">thesis</th>"), std::string::npos);
  EXPECT_NE(html.find("<th scope=\"col\">Δ</th>"), std::string::npos);
  EXPECT_NE(html.find("class=\"verdict "), std::string::npos);
}

// The clearance section discusses the calibrated flank with numbers read from results.json:
// quadrupling the fitted stiffness in results.json doubles the flank's mode frequency in the text.
TEST_F(Report, DiscussesTheCalibratedFlankFromResults) {
  const auto results = nlohmann::json::parse(read_file(study_ / "results.json"));
  const auto& sections = results.at("sections");
  if (!sections.contains("clearance") || !sections.contains("link_mode")) {
    GTEST_SKIP() << "no clearance or link-mode section in the " << source_;
  }
  const std::string html = read_file(study_ / "report.html");
  const auto clearance = html.find("<section id=\"clearance\"");
  const auto flank = html.find("The calibrated flank");
  ASSERT_NE(flank, std::string::npos);
  EXPECT_GT(flank, clearance);
  EXPECT_LT(flank, html.find("<section id=\"simulated\""));
  const std::string script =
      "import sys, json, math; sys.path.insert(0, sys.argv[1]); import make_report as mr;"
      "r = json.load(open(sys.argv[2])); cl = r['sections']['clearance'];"
      "f = lambda k: mr.fmt(math.sqrt(k / cl['link_inertia_kg_m2']) / (2 * math.pi), 3);"
      "a = mr.flank_discussion(mr.Context(r), r); k = cl['stiffness_n_m_per_rad_pow_n'];"
      "cl['stiffness_n_m_per_rad_pow_n'] = 4 * k; b = mr.flank_discussion(mr.Context(r), r);"
      "ok = abs(cl['exponent'] - 1) >= 0.1 or (f(k) + ' Hz' in a and f(4 * k) + ' Hz' in b);"
      "print(f(k), f(4 * k)); sys.exit(0 if a and a != b and ok else 1)";
  const Shell r = run("/usr/bin/python3 -c \"" + script + "\" " + quote(python_dir()) + " " +
                      quote(study_ / "results.json"));
  EXPECT_EQ(r.exit_code, 0) << r.out;
}

TEST_F(Report, ChromiumLoadsEveryFigure) {
  if (!have_chromium()) GTEST_SKIP() << "chromium is not installed (scripts/install-deps.sh installs it)";
  const std::string html = read_file(study_ / "report.html");
  const Shell dom = dump_dom(study_ / "report.html", base_ / "chromium-profile");
  ASSERT_EQ(dom.exit_code, 0) << dom.out.substr(0, 2000);
  const std::string loaded = body_attribute(dom.out, "data-figures-loaded");
  const std::string failed = body_attribute(dom.out, "data-figures-failed");
  ASSERT_FALSE(loaded.empty()) << "the page script did not report (no data-figures-loaded on <body>)";
  EXPECT_EQ(std::stoul(loaded), count(html, "<img "));
  EXPECT_EQ(std::stoul(loaded), figures_expected(html));
  EXPECT_EQ(failed, "0") << body_attribute(dom.out, "data-figures-failed-ids");
}

TEST_F(Report, ChromiumDetectsABrokenFigure) {
  if (!have_chromium()) GTEST_SKIP() << "chromium is not installed (scripts/install-deps.sh installs it)";
  std::string html = read_file(study_ / "report.html");
  const std::string marker = "src=\"data:image/png;base64,";
  const auto pos = html.find(marker);
  ASSERT_NE(pos, std::string::npos);
  const auto end = html.find('"', pos + marker.size());
  html.replace(pos + marker.size(), end - pos - marker.size(), "iVBORw0KGgoAAAANSUhEUgAAAAEAAAAB");  // truncated PNG
  const fs::path broken = base_ / "broken.html";
  std::ofstream(broken, std::ios::binary) << html;
  const Shell dom = dump_dom(broken, base_ / "chromium-profile-broken");
  ASSERT_EQ(dom.exit_code, 0);
  EXPECT_EQ(body_attribute(dom.out, "data-figures-failed"), "1");
  EXPECT_EQ(std::stoul(body_attribute(dom.out, "data-figures-loaded")), count(html, "<img ") - 1);
}

// Issue 13: one named check of tests/report/report_checks.py per defect of the report, on the
// rendered report of the study above (or on a rewritten copy of its results.json).
Shell report_check(const std::string& name, const fs::path& study) {
  return run("/usr/bin/python3 " + quote(repo_root() / "tests" / "report" / "report_checks.py") + " " + name + " " +
             quote(study) + " " + quote(python_dir()) + " " + quote(repo_root()));
}

#define REPORT_CHECK(test, check)                      \
  TEST_F(Report, test) {                               \
    const Shell r = report_check(check, study_);       \
    EXPECT_EQ(r.exit_code, 0) << source_ << "\n" << r.out; \
  }

REPORT_CHECK(LinkModeFitStartsWhereTheFreeDecayDoes, "link-mode-fit")         // 1
REPORT_CHECK(ClearanceFitThatIdentifiedNothingIsNoFinding, "clearance-identified")  // 2
REPORT_CHECK(NoColumnOfDashesShapersNotDesignedAreNamed, "empty-columns")     // 3
REPORT_CHECK(NoTableWiderThanThePage, "layout-1400")                          // 4
REPORT_CHECK(InputShapingIsNeverReadAsTheVerb, "is-spelling")                 // 5
REPORT_CHECK(SensitivityInSmallMultiples, "sensitivity")                      // 6
REPORT_CHECK(SummaryChartColoursAndLegendsOffTheBars, "md-summary")           // 7
REPORT_CHECK(RepeatabilityAsDeviationFromTheMeanWithEq41, "repeatability")    // 8
REPORT_CHECK(FailingRowStatesItsCriterionAsFailed, "failing-criterion")       // 9
REPORT_CHECK(NothingPointsOutsideTheRepository, "outside-references")         // 10
REPORT_CHECK(OnlyTheThesisRigIsScoredAgainstTheThesis, "rig-kind")            // 11

// Issue 22: a report that survives a sceptical reader (tests/report/report_checks.py).
REPORT_CHECK(ResultsWorseThanUnshapedAreMarkedEverywhere, "worse-marked")     // 22.1
REPORT_CHECK(MissingValuesAreNullAndDashNeverZero, "missing-null")            // 22.3
REPORT_CHECK(ThesisNumbersAreQuotedAsPrinted, "thesis-verbatim")              // 22.5
REPORT_CHECK(EachRigHasItsOwnWords, "rig-words")                              // 22.2
REPORT_CHECK(TheHeaderHoldsTheFindingWithIntervals, "finding")                // 22.4, 22.7, 22.8
REPORT_CHECK(NoTwoCurvesOfARigFigureLookAlike, "figure-colours")              // 22.10
REPORT_CHECK(RigTracesAreDrawnWhereTheyRing, "zoom")                          // 22.10
REPORT_CHECK(VerdictsCompareLikeWithLike, "like-with-like")                   // 22.8
REPORT_CHECK(ModelOverlaysHaveAResidualPanel, "model-residual")              // 22.10
REPORT_CHECK(ShapingDelaysAreOnesTheShaperCanAdd, "delays")                   // 22.11
REPORT_CHECK(SteadyStateDriftIsReportedApart, "drift-apart")                 // 22.10
REPORT_CHECK(LegendsInAStripThePlotsKeepTheirWidth, "legend-strip")         // 22.10
REPORT_CHECK(SummaryBarsWithSpreadOnALogAxis, "summary-bars")               // 22.10
REPORT_CHECK(TickLabelsApartOneUnshapedPairPerTable, "tick-labels")          // 22.10
REPORT_CHECK(OneNumberFormatPerColumnOneMinusSign, "number-formats")        // 22.11
REPORT_CHECK(EachDesignsColourOnlyForThatDesign, "design-colours")          // 22.10
REPORT_CHECK(AZoomedTimeAxisSaysWhichPartOfTheRecord, "zoom-note")          // 22.10
REPORT_CHECK(StudyTextsGiveEachQuantityItsUnit, "study-texts")              // 22.10
REPORT_CHECK(BootstrapIntervalsMatchANumPyReference, "bootstrap-reference")   // 22.4
REPORT_CHECK(PrintReaderFindsEachPrintDefect, "print-reader")               // 22.12
REPORT_CHECK(TheMdBandIsVisibleAtAWholeMovesScale, "md-band")               // 22.10

// Issue 22 on the what-if rigs: the quick large-play study (no thesis contact law or Eq. 4.1 figure in
// its protocol) on its own rig and on the built-in worn-coupling rig (the thesis's drive and sensors,
// 1° of play on the calibrated flank, a bearing Coulomb torque) writes null, never 0, where the thesis
// gives nothing, and each report speaks of its rig from results.json's rig description — not
// calibrated to the thesis, not scored, its documented joint beside the fit. A rig the build does not
// have is skipped.
struct WhatIfRig {
  const char* rig_option;   // "" for the protocol's own rig
  const char* kind;
};

class ReportOtherRig : public ::testing::TestWithParam<WhatIfRig> {};

TEST_P(ReportOtherRig, NullsAndItsOwnWords) {
  const WhatIfRig rig = GetParam();
  const fs::path protocol = repo_root() / "studies" / "large-play-position.toml";
  if (clearshape::testing::run_cli("study --help").exit_code != 0 || !fs::exists(protocol)) {
    GTEST_SKIP() << "clearshape study or the large-play protocol is not available";
  }
  const fs::path dir = fs::temp_directory_path() / ("clearshape_report_" + std::string(rig.kind) + "_" +
                                                    std::to_string(::getpid()));
  fs::remove_all(dir);
  const std::string option = *rig.rig_option ? std::string(" --rig ") + rig.rig_option : std::string();
  const auto r = clearshape::testing::run_cli("study " + quote(protocol) + option + " --quick --out " + quote(dir));
  if (*rig.rig_option && r.exit_code == 2 && r.err.find(rig.rig_option) != std::string::npos) GTEST_SKIP() << r.err;
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_EQ(render(dir).exit_code, 0);
  const auto results = nlohmann::json::parse(read_file(dir / "results.json"));
  EXPECT_EQ(results.at("rig").at("kind"), rig.kind);
  EXPECT_EQ(results.at("rig").at("calibrated_to_thesis"), false);
  EXPECT_EQ(results.at("rig").at("scored_against_thesis"), false);
  EXPECT_TRUE(results.at("rig").contains("documented"));
  for (const auto& t : results.at("tables")) {
    if (t.at("id") != "4.3-clearance") continue;
    for (const auto& c : t.at("columns")) {
      if (c.at("key") != "thesis") continue;
      for (const auto& v : c.at("thesis")) EXPECT_TRUE(v.is_null()) << "a thesis value where the thesis gives none: " << v;
    }
  }
  for (const char* check : {"missing-null", "rig-words", "worse-marked", "finding", "figure-colours"}) {
    const Shell c = report_check(check, dir);
    EXPECT_EQ(c.exit_code, 0) << check << "\n" << c.out;
  }
  const std::string html = read_file(dir / "report.html");
  EXPECT_EQ(html.find("calibrated to the thesis's <em>unshaped</em>"), std::string::npos);
  EXPECT_EQ(html.find("agreement with the thesis's shaped trials"), std::string::npos);
  EXPECT_NE(html.find(results.at("rig").at("summary").get<std::string>().substr(0, 40)), std::string::npos);
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(WhatIf, ReportOtherRig,
                         ::testing::Values(WhatIfRig{"", "simulated-large-play"},
                                           WhatIfRig{"worn-coupling", "simulated-worn-coupling"}),
                         [](const ::testing::TestParamInfo<WhatIfRig>& rig) {  // not `info`: -Wshadow
                           return *rig.param.rig_option ? std::string("WornCoupling") : std::string("LargePlay");
                         });

// Issue 22.13: every number README.md and docs/*.md quote from the full position study (their
// doc-numbers markers, e.g. docs/cli.md's Table B.6) is that study's output, checked by
// scripts/check-doc-numbers.py as `make run` does, so the docs fail when the study drifts. Issue
// 22.9: README's figure is that study's rig-B.1 as python/readme_figure.py draws it (make run
// redraws it): its record (title, legend with Eq. 5.1's numbers) must match a fresh drawing.
TEST(ReportDocs, DocsAndReadmeShowTheFullStudy) {
  const fs::path protocol = repo_root() / "studies" / "thesis-position.toml";
  if (clearshape::testing::run_cli("study --help").exit_code != 0) GTEST_SKIP() << "clearshape study is not available";
  const fs::path dir = fs::temp_directory_path() / ("clearshape_report_full_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const auto r = clearshape::testing::run_cli("study " + quote(protocol) + " --out " + quote(dir));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Shell numbers = run("/usr/bin/python3 " + quote(repo_root() / "scripts" / "check-doc-numbers.py") +
                            " --only thesis-position --results thesis-position=" + quote(dir / "results.json"));
  EXPECT_EQ(numbers.exit_code, 0) << numbers.out;
  EXPECT_NE(numbers.out.find(" 0 drifted"), std::string::npos) << numbers.out;
  EXPECT_EQ(numbers.out.find(" 0 quotes checked"), std::string::npos) << "no thesis-position quote marked:\n" << numbers.out;
  const fs::path png = dir / "readme" / "step20-zvdd.png";
  const Shell f = run("/usr/bin/python3 " + quote(python_dir() / "readme_figure.py") + " " + quote(dir) + " " + quote(png));
  ASSERT_EQ(f.exit_code, 0) << f.out;
  const fs::path committed = repo_root() / "docs" / "figures" / "step20-zvdd.json";
  EXPECT_EQ(nlohmann::json::parse(read_file(png.parent_path() / "step20-zvdd.json")),
            nlohmann::json::parse(read_file(committed)))
      << "README's figure is stale: `make run` redraws docs/figures/step20-zvdd.png and .json; commit them";
  fs::remove_all(dir);
}

// The report as its readers see it: laid out by Chromium at 1400 px, nothing runs past the page's
// column (layout.json lists any table or figure that does), and printed to PDF. With
// $CLEARSHAPE_TEST_ARTEFACTS set (CI), one screenshot per section is kept there as well (about
// 20 s more); the PDF and layout.json always go to $CLEARSHAPE_TEST_ARTEFACTS or ./artefacts.
TEST_F(Report, ReadsAt1400PxAndInPrint) {
  if (!have_chromium()) GTEST_SKIP() << "chromium is not installed (scripts/install-deps.sh installs it)";
  const char* env = std::getenv("CLEARSHAPE_TEST_ARTEFACTS");
  const bool shots = env != nullptr && *env != '\0';
  const fs::path dir = (shots ? fs::path(env) : fs::current_path() / "artefacts") / "report-1400px";
  fs::remove_all(dir);
  const Shell r = run("/usr/bin/python3 " + quote(python_dir() / "report_shots.py") + " " +
                      quote(study_ / "report.html") + " " + quote(dir) + (shots ? "" : " --no-shots"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const auto layout = nlohmann::json::parse(read_file(dir / "layout.json"));
  EXPECT_TRUE(layout.at("overflow").empty()) << "cut off at 1400 px: " << layout.at("overflow").dump();
  const std::string html = read_file(study_ / "report.html");
  for (const char* id : {"setup", "consistency", "identification", "clearance", "simulated", "rig",
                         "ambiguities", "differences"}) {
    if (!shots || html.find(std::string("<section id=\"") + id + "\"") == std::string::npos) continue;
    EXPECT_EQ(read_file(dir / (std::string(id) + ".png")).substr(0, 4), "\x89PNG") << id;
  }
  EXPECT_EQ(read_file(dir / "report.pdf").substr(0, 5), "%PDF-");
  RecordProperty("artefacts", dir.string());
}

// Issue 22.12: on a phone (Chromium's mobile emulation: 390 × 844 CSS px at 3 device pixels per px,
// touch, a mobile user agent; report_shots.py --phone) the page lays itself out at the phone's width
// (its viewport tag honoured: a page without one is laid out at 980 px and zoomed out), nothing runs
// past the screen outside its own scroll box and no text is squeezed to nothing. Without the page's
// narrow-screen rules the same check finds the page 549 px wide, 323 px past the screen.
TEST_F(Report, ReadsOnAPhone) {
  if (!have_chromium()) GTEST_SKIP() << "chromium is not installed (scripts/install-deps.sh installs it)";
  if (run("command -v chromedriver && /usr/bin/python3 -c 'import selenium'").exit_code != 0)
    GTEST_SKIP() << "chromium-driver or python3-selenium is not installed (scripts/install-deps.sh installs them)";
  const char* env = std::getenv("CLEARSHAPE_TEST_ARTEFACTS");
  const bool shots = env != nullptr && *env != '\0';
  const fs::path dir = (shots ? fs::path(env) : fs::current_path() / "artefacts") / "report-phone";
  fs::remove_all(dir);
  const Shell r = run("/usr/bin/python3 " + quote(python_dir() / "report_shots.py") + " " +
                      quote(study_ / "report.html") + " " + quote(dir) + " --phone --no-pdf" +
                      (shots ? "" : " --no-shots"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const auto layout = nlohmann::json::parse(read_file(dir / "layout.json"));
  EXPECT_EQ(layout.at("viewport").at("width"), 390) << "the page did not lay itself out for the phone";
  EXPECT_EQ(layout.at("viewport").at("device_pixel_ratio"), 3);
  EXPECT_EQ(layout.at("page_overflow_px"), 0);
  EXPECT_TRUE(layout.at("offscreen").empty()) << "lost on the phone: " << layout.at("offscreen").dump();
  // A table scrolled in its box keeps its caption and row labels in view at the scroll's start and end.
  EXPECT_TRUE(layout.at("in_box").empty()) << "out of the scroll box on the phone: " << layout.at("in_box").dump();
}

// Issue 22.12: printed on Letter and on A4 (python/report_print.py reads each block's page from the
// PDF's link rectangles), no heading or table caption ends a page apart from what follows it, no
// compared number's explanation row is on another page than its number, no figure is cut in two, and
// no page but the last is less than half full (a figure too tall to fit below the text).
TEST_F(Report, ReadsInPrintOnLetterAndA4) {
  if (!have_chromium()) GTEST_SKIP() << "chromium is not installed (scripts/install-deps.sh installs it)";
  const char* env = std::getenv("CLEARSHAPE_TEST_ARTEFACTS");
  const fs::path dir = (env != nullptr && *env != '\0' ? fs::path(env) : fs::current_path() / "artefacts") / "report-print";
  fs::remove_all(dir);
  for (const char* paper : {"letter", "a4"}) {
    const Shell r = run("/usr/bin/python3 " + quote(python_dir() / "report_print.py") + " " + quote(study_ / "report.html") +
                        " " + quote(dir) + " --paper " + paper);
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const auto print = nlohmann::json::parse(read_file(dir / ("print-" + std::string(paper) + ".json")));
    EXPECT_GT(print.at("blocks").get<int>(), 50) << paper << ": the blocks were not found in the PDF";
    for (const char* defect : {"stranded", "split_reasons", "split_figures", "half_empty"}) {
      EXPECT_TRUE(print.at(defect).empty()) << paper << " " << defect << ": " << print.at(defect).dump();
    }
  }
  RecordProperty("artefacts", dir.string());
}

TEST(ReportDeterminism, SameInputsSameFigureBytes) {
  const fs::path base = fs::temp_directory_path() / ("clearshape_report_det_" + std::to_string(::getpid()));
  fs::remove_all(base);
  write_fixture(base / "a");
  write_fixture(base / "b");
  ASSERT_EQ(render(base / "a").exit_code, 0);
  ASSERT_EQ(render(base / "b").exit_code, 0);
  std::size_t compared = 0;
  for (const auto& e : fs::directory_iterator(base / "a" / "figures")) {
    const fs::path other = base / "b" / "figures" / e.path().filename();
    ASSERT_TRUE(fs::exists(other)) << other;
    EXPECT_EQ(read_file(e.path()), read_file(other)) << e.path().filename() << " differs between two renders";
    ++compared;
  }
  EXPECT_GE(compared, 2U);
  EXPECT_EQ(read_file(base / "a" / "report.html"), read_file(base / "b" / "report.html"));
  fs::remove_all(base);
}

// The report's fallback for Eq. 5.1 (a mean-deviation figure without M and start) replicates
// metrics::mean_deviation: same MD and start index as the golden cases (gen_metrics.py: crossing
// rule; gen_mean_deviation.py: band entry and the options), to 1e-12.
TEST(ReportMath, MeanDeviationReplicaMatchesGolden) {
  const std::string script =
      "import sys, json; sys.path.insert(0, sys.argv[1]);"
      "from clearshape_plot.figures import steady_state_mean_deviation as f, eq_5_1;"
      "from clearshape_plot.data import CsvCache;"
      "c = CsvCache(sys.argv[2]); t = c.column('metrics_signals.csv', 'time_s');"
      "e = json.load(open(sys.argv[2] + '/metrics_expected.json'))['mean_deviation'];"
      "bad = [k for k, v in e.items() if k in c.table('metrics_signals.csv') and "
      "(abs(f(t, c.column('metrics_signals.csv', k))[0] - v['mean_deviation']) > 1e-12 or "
      "f(t, c.column('metrics_signals.csv', k))[2] != v['start_index'])];"
      "n = sum(1 for k in e if k in c.table('metrics_signals.csv'));"
      "tb = c.column('mean_deviation_signals.csv', 'time_s');"
      "g = json.load(open(sys.argv[2] + '/mean_deviation_expected.json'))['cases'];"
      "r = [(x, eq_5_1(tb, c.column('mean_deviation_signals.csv', x['signal']), **x['options'])) for x in g];"
      "bad += [x['signal'] for x, y in r if abs(y['mean_deviation'] - x['expected']['mean_deviation']) > 1e-12 "
      "or y['start_index'] != x['expected']['start_index'] or y['start_rule'] != x['expected']['start_rule']];"
      "n += len(r);"
      "print('compared', n, 'bad', bad); sys.exit(1 if bad or n < 12 else 0)";
  const Shell r = run("/usr/bin/python3 -c \"" + script + "\" " + quote(python_dir()) + " " +
                      quote(fs::path(CLEARSHAPE_GOLDEN_DIR)));
  EXPECT_EQ(r.exit_code, 0) << r.out;
}

TEST(ReportInput, MissingResultsIsBadInput) {
  const fs::path dir = fs::temp_directory_path() / ("clearshape_report_empty_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const Shell r = render(dir);
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_NE(r.out.find("results.json"), std::string::npos) << r.out;
  fs::remove_all(dir);
}

}  // namespace
