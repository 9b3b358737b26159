// Requirements on `hertzgear report DIR`: it turns the artifacts of a run (flat or nested in stage
// folders) into DIR/report/index.html with PNG figures that exist and carry content, it leaves a
// figure out with a note when its input is absent, it draws the stiffness's Fourier series only
// from the coefficients stiffness.json carries, it rejects a missing or empty directory with
// exit code 2, it never leaves a half-written file under a final name, and the page loads in a
// browser (headless Chromium) with every image present and a screenshot that is not blank. It
// reads a 400 MB time series within a stated memory bound; an artifact that cannot be parsed or
// a report folder that is a file ends it with exit 2 and one line naming the file, an
// unforeseen failure with exit 1 and one line.
//
// The artifacts are synthetic test data from tests/support/make_report_artifacts.py (closed-form
// signals in the column contract of the stiffness, dynamics, sweep and accuracy commands); the
// scene files (used_parameters.prm, run.json) come from a real `hertzgear check`.
#include "tests/support/run_command.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <regex>
#include <set>

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
        "contact_pattern_misalignment.png", "contact_lines.png", "tolerance_study.png"})
    EXPECT_EQ(on_page.count(expected), 1u) << expected << " missing from the page";
  // The load and design map is tabulated per case: a tolerance study of 2 crownings x 2 helix
  // slopes x 3 misalignments x 4 torques (tests/support/make_report_artifacts.py), whose spread
  // over the 12 designs at each torque the tolerance-study figure draws.
  EXPECT_THAT(html, HasSubstr("Load and design map: 48 cases"));
  EXPECT_THAT(html, HasSubstr("every design it ran (up to 12: lead"));

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

// A table with a header and no rows shall cost only its own figures: the report still finishes,
// says so on the page and draws the spectrum from the time series instead.
TEST(Report, TableWithoutRowsIsNotedAndTheRestIsDrawn)
{
  const fs::path dir = make_run("report_corrupt", "--layout nested");
  std::ofstream(dir / "dynamics" / "spectrum.csv", std::ios::trunc)
    << "frequency_Hz,amplitude_um\n";
  const auto r = run_hertzgear("report " + quoted(dir));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string html = slurp(dir / "report" / "index.html");
  EXPECT_THAT(html, HasSubstr("spectrum.csv holds no data rows"));
  EXPECT_THAT(html, HasSubstr("FFT of the steady part of timeseries.csv"));
  expect_images_present(dir / "report", image_sources(html));
  EXPECT_THAT(image_sources(html), ::testing::Contains("dte_penetration.png"));
  EXPECT_THAT(image_sources(html), ::testing::Contains("spectrum.png"));
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

// ---------------------------------------------------------------------------------------------
// Bounded memory and the report's own failures
// ---------------------------------------------------------------------------------------------

namespace
{
  // The exit code of a shell command and the peak resident memory (kB) of it and every process
  // below it: wait4 reports the largest maximum RSS of the child and the descendants it waited
  // for (here /bin/sh, hertzgear and the report's Python).
  struct Measured
  {
    int  exit_code = -1;
    long peak_rss_kb = 0;
  };

  Measured measure(const std::string &command)
  {
    const pid_t pid = ::fork();
    if (pid == 0)
      {
        ::execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char *>(nullptr));
        ::_exit(127);
      }
    Measured m;
    int           status = 0;
    struct rusage usage  = {};
    if (pid > 0 && ::wait4(pid, &status, 0, &usage) == pid)
      {
        m.exit_code   = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        m.peak_rss_kb = usage.ru_maxrss;
      }
    return m;
  }

  // Appends copies of the data rows of the CSV `file` (time in its first column) shifted in time
  // by whole copies of the recorded window until the file holds at least `bytes`: a consistent
  // longer history (time increasing, the same motion repeated).
  void grow_timeseries(const fs::path &file, const std::uintmax_t bytes)
  {
    std::ifstream            in(file);
    std::string              header, line;
    std::vector<double>      times;
    std::vector<std::string> rests;
    std::getline(in, header);
    while (std::getline(in, line))
      if (!line.empty())
        {
          const auto comma = line.find(',');
          times.push_back(std::stod(line.substr(0, comma)));
          rests.push_back(line.substr(comma));
        }
    ASSERT_GT(times.size(), 2u);
    const double span = times.back() - times.front();
    std::uintmax_t size = fs::file_size(file);
    std::ofstream  out(file, std::ios::app);
    char           time_text[64];
    for (int copy = 1; size < bytes; ++copy)
      for (std::size_t i = 1; i < times.size(); ++i) // the first row equals the last one before
        {
          const int n = std::snprintf(time_text, sizeof time_text, "%.12g", times[i] + copy * span);
          out.write(time_text, n);
          out << rests[i] << '\n';
          size += n + rests[i].size() + 1;
        }
  }
} // namespace

// The report shall read a 400 MB timeseries.csv with bounded memory: at most 1 GB of peak
// resident memory for the whole `hertzgear report`, the bound docs/report.md states ("Memory"),
// with exit 0 and a whole page with every dynamics figure, the page saying that the figures draw
// the last rows. Why 1 GB holds: the report keeps at most 6 million values of a table (48 MB, a
// few copies while a figure is drawn), Python with numpy and matplotlib takes about 150 MB, and
// the phase portrait draws at most 100 000 samples (about 120 MB in Agg); the measured peak is
// about 0.3 GB (3.8 GB when the whole file was read, and its phase portrait failed in Agg).
TEST(Report, LargeTimeseriesIsReadWithBoundedMemory)
{
  const fs::path dir = fresh_temp_dir("report_large_timeseries");
  const auto     run = run_hertzgear("dynamics " + scene_path("paper_crowned_fourier.prm") +
                                 " --set Dynamics/periods=60 --set Dynamics/transient_periods=30"
                                 " --out " + quoted(dir));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const fs::path timeseries = dir / "timeseries.csv";
  ASSERT_TRUE(fs::is_regular_file(timeseries));
  grow_timeseries(timeseries, 400'000'000);
  ASSERT_GE(fs::file_size(timeseries), 400'000'000u);

  const fs::path err = dir.string() + "_stderr.txt";
  const Measured m   = measure("'" + std::string(HERTZGEAR_EXE) + "' report " + quoted(dir) +
                             " >/dev/null 2>" + quoted(err) + " </dev/null");
  const std::string messages = slurp(err);
  fs::remove(err);
  fs::remove(timeseries); // 400 MB of temporary disk
  EXPECT_EQ(m.exit_code, 0) << messages;
  EXPECT_GT(m.peak_rss_kb, 0) << "no usage reported";
  EXPECT_LT(m.peak_rss_kb, 1024L * 1024L) << "peak memory " << m.peak_rss_kb / 1024 << " MB";
  ASSERT_TRUE(fs::is_regular_file(dir / "report" / "index.html"));
  const std::string html = slurp(dir / "report" / "index.html");
  EXPECT_THAT(html, HasSubstr("</html>"));
  EXPECT_THAT(html, HasSubstr("more than the report holds in memory"));
  const auto sources = image_sources(html);
  expect_images_present(dir / "report", sources);
  for (const char *figure : {"dte_penetration.png", "mesh_force.png", "poincare.png",
                             "phase_portrait.png", "spectrum.png"})
    EXPECT_THAT(sources, ::testing::Contains(figure));
}

// A report folder that is a regular file shall be bad input: exit 2, one message naming it, no
// Python traceback, and the file left as it was. The same for --out below a regular file.
TEST(Report, ReportFolderThatIsAFileIsBadInput)
{
  const fs::path dir = make_run("report_folder_file", "--layout flat --only dynamics");
  std::ofstream(dir / "report") << "not a folder\n";
  auto r = run_hertzgear("report " + quoted(dir));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr((dir / "report").string() + " is a file, not a folder"));
  EXPECT_THAT(r.err, ::testing::Not(HasSubstr("Traceback")));
  EXPECT_EQ(slurp(dir / "report"), "not a folder\n");

  r = run_hertzgear("report " + quoted(dir) + " --out " + quoted(dir / "report" / "sub"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr((dir / "report").string() + " is a file"));
  EXPECT_THAT(r.err, ::testing::Not(HasSubstr("Traceback")));
}

// An artifact that cannot be parsed (a table cut in the middle of a row, truncated JSON, a table
// without the columns its figures need, bytes that are not text) shall be bad input: exit 2 with
// one message naming the file, no traceback, and the report of before left whole with no
// temporary file beside it (every artifact is read before the first write).
TEST(Report, GarbledArtifactIsBadInput)
{
  const fs::path dir = make_run("report_garbled", "--layout nested");
  ASSERT_EQ(run_hertzgear("report " + quoted(dir)).exit_code, 0);
  const std::string page_before = slurp(dir / "report" / "index.html");
  const fs::path    dynamics    = dir / "dynamics";
  const std::string timeseries  = slurp(dynamics / "timeseries.csv");
  const std::string summary     = slurp(dynamics / "summary.json");

  struct Case
  {
    std::string file, content, message;
  };
  // The time series cut after the second field of a row, as an interrupted copy leaves it.
  const std::size_t cut = timeseries.find(',', timeseries.find(',', timeseries.size() / 2) + 1);
  const std::vector<Case> cases = {
    {"timeseries.csv", timeseries.substr(0, cut + 1), "stops without a line end: a truncated"},
    {"timeseries.csv", timeseries + "1,2,3\n", "has 3 fields where the header has 6"},
    {"summary.json", summary.substr(0, summary.size() / 2), "is not valid JSON"},
    {"timeseries.csv", "time_s,speed\n0,1\n1,2\n", "has no DTE column"},
    {"timeseries.csv", timeseries + "\xff\xfe\x01\n", "is not UTF-8 text"},
  };
  for (const auto &c : cases)
    {
      std::ofstream(dynamics / c.file, std::ios::trunc | std::ios::binary) << c.content;
      const auto r = run_hertzgear("report " + quoted(dir));
      EXPECT_EQ(r.exit_code, 2) << c.file << ": " << r.err;
      EXPECT_THAT(r.err, HasSubstr((dynamics / c.file).string())) << "names the file";
      EXPECT_THAT(r.err, HasSubstr(c.message));
      EXPECT_THAT(r.err, ::testing::Not(HasSubstr("Traceback")));
      EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line: " << r.err;
      EXPECT_EQ(slurp(dir / "report" / "index.html"), page_before) << c.file;
      for (const auto &entry : fs::directory_iterator(dir))
        EXPECT_EQ(entry.path().filename().string().find(".hg-partial"), std::string::npos)
          << entry.path();
      std::ofstream(dynamics / "timeseries.csv", std::ios::trunc) << timeseries;
      std::ofstream(dynamics / "summary.json", std::ios::trunc) << summary;
    }
}

// An unforeseen failure of the report script shall end with exit 1 and one line
// "report script failed: <what>", printed once (hertzgear adds no second message), with the
// traceback only when HERTZGEAR_DEBUG is set. The failure is injected by a script that runs the
// real one with its page writer replaced.
TEST(Report, UnforeseenScriptFailureIsOneLineAndExitOne)
{
  const fs::path dir     = make_run("report_unforeseen", "--layout flat --only dynamics");
  const fs::path scripts = fs::path(HERTZGEAR_SOURCE_DIR) / "scripts";
  const fs::path failing = dir.string() + "_failing_report.py";
  std::ofstream(failing) << "import sys\n"
                            "sys.path.insert(0, " << quoted(scripts) << ")\n"
                            "import hertzgear_report as h\n"
                            "def fail(art, out_dir):\n"
                            "    raise RuntimeError('injected failure')\n"
                            "h.report.write_report = fail\n"
                            "sys.exit(h.run())\n";
  const std::string env = "HERTZGEAR_REPORT_SCRIPT=" + quoted(failing) + " ";
  auto r = run_hertzgear("report " + quoted(dir), "env " + env);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_THAT(r.err, HasSubstr("report script failed: RuntimeError: injected failure"));
  EXPECT_THAT(r.err, ::testing::Not(HasSubstr("Traceback")));
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line: " << r.err;
  EXPECT_FALSE(fs::exists(dir / "report")) << "no page from a failed report";

  r = run_hertzgear("report " + quoted(dir), "env HERTZGEAR_DEBUG=1 " + env);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_THAT(r.err, HasSubstr("report script failed: RuntimeError: injected failure"));
  EXPECT_THAT(r.err, HasSubstr("Traceback"));
  fs::remove(failing);
}
