// Requirements on `hertzgear report DIR`: it turns the artifacts of a run (flat or nested in stage
// folders) into DIR/report/index.html with PNG figures that exist and carry content, it leaves a
// figure out with a note when its input is absent, it draws the stiffness's Fourier series only
// from the coefficients stiffness.json carries, it rejects a missing or empty directory with
// exit code 2, it never leaves a half-written file under a final name, and the page loads in a
// browser (headless Chromium) with every image present and a screenshot that is not blank.
//
// The artifacts are synthetic test data from tests/support/make_report_artifacts.py (closed-form
// signals in the column contract of the stiffness, dynamics, sweep and accuracy commands); the
// scene files (used_parameters.prm, run.json) come from a real `hertzgear check`.
#include "tests/support/run_command.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <set>
#include <unistd.h>

using namespace hertzgear::testing;
using ::testing::HasSubstr;
namespace fs = std::filesystem;

namespace
{
  std::string python()
  {
    // Debian's python3 carries python3-matplotlib (the one the report command prefers too).
    return ::access("/usr/bin/python3", X_OK) == 0 ? "/usr/bin/python3" : "python3";
  }

  int run_shell(const std::string &command)
  {
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  std::string quoted(const fs::path &p) { return "'" + p.string() + "'"; }

  // A run directory with a real scene record and synthetic artifacts.
  fs::path make_run(const std::string &name, const std::string &helper_arguments)
  {
    const fs::path dir = fresh_temp_dir(name);
    const auto     check = run_hertzgear("check " + scene_path("paper_crowned.prm") + " --out " +
                                     quoted(dir));
    EXPECT_EQ(check.exit_code, 0) << check.err;
    const std::string helper =
      std::string(HERTZGEAR_SOURCE_DIR) + "/tests/support/make_report_artifacts.py";
    EXPECT_EQ(run_shell(python() + " '" + helper + "' " + quoted(dir) + " " + helper_arguments), 0);
    return dir;
  }

  // The file names of every <img src="..."> on the page.
  std::vector<std::string> image_sources(const std::string &html)
  {
    std::vector<std::string> sources;
    const std::regex         img(R"re(<img[^>]*\ssrc="([^"]+)")re");
    const std::sregex_iterator end;
    for (auto it = std::sregex_iterator(html.begin(), html.end(), img); it != end; ++it)
      sources.push_back((*it)[1]);
    return sources;
  }

  bool is_complete_png(const fs::path &p)
  {
    const std::string bytes = slurp(p);
    // PNG signature at the start and the IEND chunk (with its CRC) at the very end.
    return bytes.size() > 20 && bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0 &&
           bytes.compare(bytes.size() - 8, 4, "IEND") == 0;
  }

  // Every image on the page exists next to it, is a whole PNG and is not trivial. A plot with
  // axes, labels and a curve is tens of kB; 5 kB is far above an empty or 1-pixel PNG (< 1 kB).
  void expect_images_present(const fs::path &report_dir, const std::vector<std::string> &sources)
  {
    for (const auto &src : sources)
      {
        const fs::path png = report_dir / src;
        ASSERT_TRUE(fs::is_regular_file(png)) << src << " is on the page but not on disk";
        EXPECT_TRUE(is_complete_png(png)) << src;
        EXPECT_GT(fs::file_size(png), 5000u) << src << " is suspiciously small";
      }
  }
} // namespace

// The report shall draw every figure its artifacts allow, from a nested run directory
// (stiffness/, dynamics/, sweep/, accuracy/), each referenced PNG existing and non-trivial.
TEST(Report, NestedRunGivesEveryFigure)
{
  const fs::path dir = make_run("report_nested", "--layout nested");
  const auto     r   = run_hertzgear("report " + quoted(dir));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const fs::path report = dir / "report";
  ASSERT_TRUE(fs::is_regular_file(report / "index.html"));
  const std::string html = slurp(report / "index.html");
  EXPECT_THAT(html, HasSubstr("</html>"));

  const auto sources = image_sources(html);
  expect_images_present(report, sources);
  const std::set<std::string> on_page(sources.begin(), sources.end());
  for (const char *expected :
       {"stiffness_cycle.png", "ste_load_sharing.png", "contact_per_position.png",
        "contact_pressure_map.png", "dte_penetration.png", "mesh_force.png", "poincare.png",
        "phase_portrait.png", "force_penetration.png", "spectrum.png", "sweep_rms.png",
        "bifurcation.png", "accuracy_1.png", "ste_against_torque.png",
        "misalignment_pressure_centre.png", "contact_pattern_torque.png",
        "contact_pattern_misalignment.png"})
    EXPECT_EQ(on_page.count(expected), 1u) << expected << " missing from the page";
  // The load and design map is tabulated per case.
  EXPECT_THAT(html, HasSubstr("Load and design map: 14 cases"));

  // Every figure has a caption; the scene's effects and the summary are tabulated.
  const std::regex figure_without_caption(R"(<figure><img[^>]*></figure>)");
  EXPECT_FALSE(std::regex_search(html, figure_without_caption));
  EXPECT_THAT(html, HasSubstr("hertzian_layer"));
  EXPECT_THAT(html, HasSubstr("rms_dte_um"));
  EXPECT_THAT(html, HasSubstr("crowning_um"));
  // b_c and f_m are taken from summary.json when it states them.
  EXPECT_THAT(html, HasSubstr("b<sub>c</sub> = 58.6 µm, from summary.json"));
  EXPECT_THAT(html, HasSubstr("f<sub>m</sub> = 57.5 Hz"));
  // The stiffness lines are the Fourier series of the coefficients stiffness.json carries.
  for (const char *source :
       {"k_total: Fourier coefficients of stiffness.json (k_total_N_per_m)",
        "k_rest: Fourier coefficients of stiffness.json (k_rest_N_per_m)",
        "k_hertz: Fourier coefficients of stiffness.json (k_hertz_N_per_m_pow_n)"})
    EXPECT_THAT(html, HasSubstr(source));
  // No temporary file is left behind by a report that finished.
  for (const auto &entry : fs::directory_iterator(report))
    EXPECT_EQ(entry.path().filename().string().find(".hg-partial"), std::string::npos)
      << entry.path();
}

// A flat run directory with dynamics artifacts only shall give the dynamics figures and say on the
// page which figures were left out, without referencing any image it did not write.
TEST(Report, FlatDynamicsOnlyRunSkipsStiffnessFiguresWithANote)
{
  const fs::path dir = make_run("report_flat", "--layout flat --only dynamics");
  const fs::path out = dir / "elsewhere";
  const auto     r   = run_hertzgear("report " + quoted(dir) + " --out " + quoted(out));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(fs::exists(dir / "report")) << "--out puts the report elsewhere";
  const std::string html    = slurp(out / "index.html");
  const auto        sources = image_sources(html);
  expect_images_present(out, sources);
  const std::set<std::string> on_page(sources.begin(), sources.end());
  EXPECT_EQ(on_page.count("dte_penetration.png"), 1u);
  EXPECT_EQ(on_page.count("spectrum.png"), 1u);
  EXPECT_EQ(on_page.count("stiffness_cycle.png"), 0u);
  EXPECT_EQ(on_page.count("sweep_rms.png"), 0u);
  EXPECT_THAT(html, HasSubstr("No stiffness.csv in this run"));
}

// A directory that does not exist or holds no artifact shall be bad input (exit 2) with a message
// that names it, and shall not get a report folder.
TEST(Report, MissingOrEmptyDirectoryIsBadInput)
{
  const fs::path dir = fresh_temp_dir("report_empty");
  fs::create_directories(dir);
  auto r = run_hertzgear("report " + quoted(dir / "nowhere"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("nowhere"));
  EXPECT_THAT(r.err, HasSubstr("does not exist"));

  r = run_hertzgear("report " + quoted(dir));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("holds no hertzgear artifact"));
  EXPECT_FALSE(fs::exists(dir / "report"));

  r = run_hertzgear("report");
  EXPECT_EQ(r.exit_code, 2) << "the run directory is required";

  r = run_hertzgear("report " + quoted(dir) + " --set 'Operating/speed_rpm=100'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("takes no --set"));
}

// An unreadable artifact shall cost only its own figures: the report still finishes and says so.
TEST(Report, CorruptArtifactIsNotedAndTheRestIsDrawn)
{
  const fs::path dir = make_run("report_corrupt", "--layout nested");
  std::ofstream(dir / "dynamics" / "spectrum.csv", std::ios::trunc) << "frequency_Hz\n";
  std::ofstream(dir / "dynamics" / "summary.json", std::ios::trunc) << "{\"rms_dte_um\": 1";
  const auto r = run_hertzgear("report " + quoted(dir));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string html = slurp(dir / "report" / "index.html");
  EXPECT_THAT(html, HasSubstr("summary.json could not be read"));
  EXPECT_THAT(html, HasSubstr("spectrum.csv could not be read"));
  expect_images_present(dir / "report", image_sources(html));
  EXPECT_THAT(image_sources(html), ::testing::Contains("dte_penetration.png"));
}

// Without Fourier coefficients in stiffness.json, the stiffness figure shall draw the samples of
// stiffness.csv only and say that the coefficients are missing: the report fits no series itself.
TEST(Report, StiffnessWithoutCoefficientsDrawsSamplesOnly)
{
  const fs::path dir = make_run("report_no_coefficients", "--layout nested --only stiffness");
  std::ofstream(dir / "stiffness" / "stiffness.json", std::ios::trunc)
    << "{\"schema\": \"hertzgear-stiffness-table/1\", \"hertz_exponent\": 1.5}";
  const auto r = run_hertzgear("report " + quoted(dir));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string html = slurp(dir / "report" / "index.html");
  EXPECT_THAT(image_sources(html), ::testing::Contains("stiffness_cycle.png"));
  expect_images_present(dir / "report", image_sources(html));
  for (const char *quantity : {"k_total", "k_rest", "k_hertz"})
    EXPECT_THAT(html, HasSubstr(std::string(quantity) +
                                ": samples only, stiffness.json carries no Fourier coefficients "
                                "for it"));
  EXPECT_THAT(html, ::testing::Not(HasSubstr("Fourier coefficients of stiffness.json")));
  EXPECT_THAT(html, ::testing::Not(HasSubstr("lines the Fourier series")));
}

// An interrupted report shall leave no half-written file under a final name: whatever instant it
// is killed at, every non-temporary file in the report folder is complete.
TEST(Report, InterruptedReportLeavesNoHalfWrittenFile)
{
  const fs::path dir    = make_run("report_interrupted", "--layout nested");
  const fs::path script = fs::path(HERTZGEAR_SOURCE_DIR) / "scripts" / "hertzgear_report.py";
  for (const char *after : {"1.5", "3", "5"})
    {
      fs::remove_all(dir / "report");
      run_shell("timeout -s KILL " + std::string(after) + " " + python() + " " + quoted(script) +
                " " + quoted(dir) + " >/dev/null 2>&1");
      if (!fs::exists(dir / "report"))
        continue; // killed before the first write: nothing to check
      for (const auto &entry : fs::directory_iterator(dir / "report"))
        {
          const std::string name = entry.path().filename().string();
          if (name.front() == '.')
            continue; // a temporary name no reader trusts
          if (entry.path().extension() == ".png")
            {
              EXPECT_TRUE(is_complete_png(entry.path())) << name << " is truncated";
            }
          else if (name == "index.html")
            {
              EXPECT_THAT(slurp(entry.path()), HasSubstr("</html>"));
            }
        }
    }
}

// The page shall load in a browser with no missing image, and its screenshot shall not be blank.
namespace
{
  // The report of `dir` loads in headless Chromium with at least `min_images` images, none
  // broken, and its screenshot is not blank. Skips when Chromium is not installed.
  void expect_report_renders_in_chromium(const fs::path &dir, const int min_images)
  {
    std::string chromium;
    for (const char *c : {"/usr/bin/chromium", "/usr/bin/chromium-browser"})
      if (::access(c, X_OK) == 0)
        chromium = c;
    if (chromium.empty())
      GTEST_SKIP() << "chromium is not installed (apt-get install chromium); the browser check "
                      "is skipped";
    const fs::path report = dir / "report";

    // A copy of the page, in the same folder so relative image paths resolve, with a script that
    // records after the load event how many images decoded (naturalWidth > 0) and which did not.
    std::string html = slurp(report / "index.html");
    const std::string probe =
      "<script>window.addEventListener('load', function () {"
      " var bad = [], imgs = document.images;"
      " for (var i = 0; i < imgs.length; ++i)"
      "   if (!imgs[i].complete || imgs[i].naturalWidth === 0) bad.push(imgs[i].getAttribute('src'));"
      " document.body.setAttribute('data-images', imgs.length);"
      " document.body.setAttribute('data-broken', bad.join(' ') || 'none'); });</script>";
    html.replace(html.rfind("</body>"), 7, probe + "</body>");
    std::ofstream(report / "browser_check.html") << html;

    const fs::path profile = dir / "chromium-profile";
    const std::string common =
      "timeout 180 " + chromium +
      " --headless --no-sandbox --disable-gpu --disable-quic --no-first-run"
      " --disable-background-networking --disable-component-update --disable-sync"
      " --disable-dev-shm-usage --virtual-time-budget=10000 --user-data-dir=" + quoted(profile) +
      " --window-size=1280,2000 ";
    const fs::path dom = dir / "dom.html";
    ASSERT_EQ(run_shell(common + "--dump-dom 'file://" + (report / "browser_check.html").string() +
                        "' >" + quoted(dom) + " 2>/dev/null"),
              0);
    const std::string dumped = slurp(dom);
    std::smatch       m;
    ASSERT_TRUE(std::regex_search(dumped, m, std::regex(R"re(data-images="(\d+)")re")))
      << "the load probe did not run";
    EXPECT_GE(std::stoi(m[1]), min_images) << "the page should show the figures";
    EXPECT_THAT(dumped, HasSubstr("data-broken=\"none\"")) << "images that did not load";

    const fs::path shot = dir / "screenshot.png";
    ASSERT_EQ(run_shell(common + "--screenshot=" + quoted(shot) + " 'file://" +
                        (report / "index.html").string() + "' >/dev/null 2>&1"),
              0);
    ASSERT_TRUE(is_complete_png(shot));
    // Not blank: pixel standard deviation well above zero (a blank page has 0; this page with a
    // dark header, text and figures has about 0.2 on a 0..1 scale) and more than 5 % of the pixels
    // away from the page background.
    const std::string check =
      python() + " -c \"import sys, numpy as np, matplotlib.image as mi;"
                 " a = mi.imread(sys.argv[1])[..., :3]; bg = np.median(a.reshape(-1, 3), axis=0);"
                 " far = (np.abs(a - bg).max(axis=2) > 0.1).mean();"
                 " print('std %.3f, non-background %.3f' % (a.std(), far));"
                 " sys.exit(0 if a.std() > 0.05 and far > 0.05 else 1)\" " +
      quoted(shot);
    EXPECT_EQ(run_shell(check), 0) << "the screenshot looks blank";
  }
} // namespace

TEST(Report, PageRendersInHeadlessChromium)
{
  const fs::path dir = make_run("report_chromium", "--layout nested");
  const auto     r   = run_hertzgear("report " + quoted(dir));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expect_report_renders_in_chromium(dir, 10);
}

// The report that `hertzgear run` writes at its end (stiffness from closed forms, dynamics, a
// short sweep) opens in the browser with the stiffness, dynamics and sweep figures.
TEST(Report, RunOutputRendersInHeadlessChromium)
{
  const fs::path dir = fresh_temp_dir("report_run_chromium");
  const auto     r   = run_hertzgear(
    "run " + scene_path("paper_crowned.prm") +
    " --set Stiffness/source=hertz-analytic --set Dynamics/periods=60"
    " --set Dynamics/transient_periods=30 --set Sweep/enabled=true --set Sweep/points=3"
    " --set Sweep/speed_min_rpm=100 --set Sweep/speed_max_rpm=200 --set Sweep/periods_per_point=40"
    " --set Sweep/transient_periods_per_point=20 --set Sweep/mode=independent --out " + quoted(dir));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(fs::exists(dir / "report" / "index.html"));
  // The page of a run says which stages ran and why (from run.json).
  const std::string html = slurp(dir / "report" / "index.html");
  EXPECT_THAT(html, HasSubstr("Stages of this run"));
  EXPECT_THAT(html, HasSubstr("no cached result"));
  for (const char *figure : {"stiffness_cycle.png", "dte_penetration.png", "poincare.png",
                             "force_penetration.png", "sweep_rms.png", "bifurcation.png"})
    EXPECT_THAT(html, HasSubstr(figure)) << figure;
  expect_report_renders_in_chromium(dir, 10);
}
