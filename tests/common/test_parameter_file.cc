// Requirements on parameter files (common/parameter_file): what is printed parses back to the same
// values; each pattern accepts its bounds and refuses what lies beyond; errors name the source,
// the line and the key; a key set twice, an unbalanced subsection, a control character and a
// continuation line are refused; the printed form is the documented .prm layout.
#include "common/input_file.h"
#include "common/parameter_file.h"
#include "common/shown_text.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

using namespace hertzgear;
using ::testing::HasSubstr;
namespace P  = hertzgear::patterns;
namespace fs = std::filesystem;

namespace
{
  // A small parameter set with every kind of entry, nested two levels deep.
  struct Values
  {
    int                 teeth     = 23;
    double              module_mm = 3.0;
    double              stiffness = 4.17e8;
    bool                enabled   = false;
    std::string         shape     = "linear";
    std::string         file;
    std::vector<double> amplitudes;
    double              ratio = 0.015;
  };

  void declare(ParameterFile &prm, Values &v)
  {
    prm.enter_subsection("Gear pair");
    prm.enter_subsection("Pinion");
    prm.add("teeth", v.teeth, P::Integer(6, 1000), "Number of teeth (count).");
    prm.add("module_mm", v.module_mm, P::Double(0.05, 100.0), "Normal module m [mm].");
    prm.add("tip_relief_shape", v.shape, P::Selection("linear|parabolic"),
            "Shape of the tip relief along the roll length: linear or parabolic.");
    prm.leave_subsection();
    prm.leave_subsection();
    prm.enter_subsection("Stiffness");
    prm.add("k_mean_N_per_m", v.stiffness, P::Double(0.0, 1.0e13), "Mean stiffness [N/m].");
    prm.add("table_file", v.file, P::Anything(), "Stiffness JSON file.");
    prm.enter_subsection("Fourier");
    prm.add("amplitudes_N_per_m", v.amplitudes, P::List(P::Double(0.0, 1.0e13), 0, 4, ","),
            "Harmonic amplitudes [N/m], comma separated.");
    prm.leave_subsection();
    prm.leave_subsection();
    prm.enter_subsection("Sweep");
    prm.add("enabled", v.enabled, P::Bool(), "Whether the sweep runs (true/false).");
    prm.add("damping_ratio", v.ratio, P::Double(0.0, 1.0), "Damping ratio [dimensionless].");
    prm.leave_subsection();
  }

  // The message of the ParameterFileError that parsing `text` (named `source`) throws.
  std::string parse_error(const std::string &text, const std::string &source = "scene.prm")
  {
    Values        v;
    ParameterFile prm;
    declare(prm, v);
    std::istringstream in(text);
    try
      {
        prm.parse(in, source);
      }
    catch (const ParameterFileError &e)
      {
        return e.what();
      }
    return "(no error)";
  }

  Values parsed(const std::string &text)
  {
    Values        v;
    ParameterFile prm;
    declare(prm, v);
    std::istringstream in(text);
    prm.parse(in, "test.prm");
    return v;
  }
} // namespace

TEST(ParameterFile, PrintedFormsParseBackToTheSameValues)
{
  // Requirement: the documented and the short form of any state read back as that state, and
  // print the same text again (used_parameters.prm reproduces a run; the short form is hashed).
  Values        v;
  ParameterFile prm;
  declare(prm, v);
  prm.set("Gear pair/Pinion", "teeth", "31");
  prm.set("Gear pair/Pinion", "module_mm", "2.5");
  prm.set("Stiffness", "table_file", "tables/a b.json");
  prm.set("Stiffness/Fourier", "amplitudes_N_per_m", "1e7, 2.5e6, 0.1");
  prm.set("Sweep", "enabled", "true");
  for (const auto style : {ParameterFile::Style::documented, ParameterFile::Style::short_form})
    for (const auto order : {ParameterFile::Order::declaration, ParameterFile::Order::alphabetical})
      {
        const std::string text = prm.print(style, order);
        Values            w;
        ParameterFile     again;
        declare(again, w);
        std::istringstream in(text);
        again.parse(in, "printed.prm");
        EXPECT_EQ(w.teeth, 31);
        EXPECT_DOUBLE_EQ(w.module_mm, 2.5);
        EXPECT_EQ(w.file, "tables/a b.json");
        EXPECT_EQ(w.amplitudes, (std::vector<double>{1e7, 2.5e6, 0.1}));
        EXPECT_TRUE(w.enabled);
        EXPECT_EQ(w.stiffness, 4.17e8);
        EXPECT_EQ(again.print(style, order), text);
      }
  // The variables hold what was set.
  EXPECT_EQ(v.teeth, 31);
  EXPECT_EQ(v.amplitudes.size(), 3u);
}

TEST(ParameterFile, DefaultsArePrintedInShortestStreamForm)
{
  // Requirement: a default prints as C++ streams print a double (4.17e+08, 1e-10, 0.1172, 3), and
  // with more digits where six would not read back as the same number.
  double a = 4.17e8, b = 1e-10, c = 0.1172, d = 3.0, e = 0.1 + 0.2, f = 1e6;
  int    n = -7;
  ParameterFile prm;
  const P::Double any(-1e300, 1e300);
  EXPECT_EQ(prm.add("a", a, any, "a").default_text(), "4.17e+08");
  EXPECT_EQ(prm.add("b", b, any, "b").default_text(), "1e-10");
  EXPECT_EQ(prm.add("c", c, any, "c").default_text(), "0.1172");
  EXPECT_EQ(prm.add("d", d, any, "d").default_text(), "3");
  EXPECT_EQ(prm.add("e", e, any, "e").default_text(), "0.30000000000000004");
  EXPECT_EQ(prm.add("f", f, any, "f").default_text(), "1e+06");
  EXPECT_EQ(prm.add("n", n, P::Integer(-10, 10), "n").default_text(), "-7");
}

TEST(Patterns, DescriptionsReadAsTheSceneReferenceShowsThem)
{
  // Requirement: docs/scenes.md and the error messages show these exact texts.
  EXPECT_EQ(P::Integer(6, 1000).description(), "[Integer range 6...1000 (inclusive)]");
  EXPECT_EQ(P::Double(0.05, 100).description(), "[Double 0.05...100 (inclusive)]");
  EXPECT_EQ(P::Double(1e-16, 1e-2).description(), "[Double 1e-16...0.01 (inclusive)]");
  EXPECT_EQ(P::Double(0, 1e6).description(), "[Double 0...1e+06 (inclusive)]");
  EXPECT_EQ(P::Bool().description(), "[Bool]");
  EXPECT_EQ(P::Anything().description(), "[Anything]");
  EXPECT_EQ(P::Selection("fem|table | fourier").description(), "[Selection fem|table|fourier ]");
  EXPECT_EQ(P::List(P::Double(0, 1e13), 0, 64, ",").description(),
            "[List of <[Double 0...1e+13 (inclusive)]> of length 0...64 (inclusive)]");
  EXPECT_EQ(P::List(P::Double(-1, 1), 1, 3, ";").description(),
            "[List of <[Double -1...1 (inclusive)]> of length 1...3 (inclusive) separated by <;>]");
}

TEST(Patterns, IntegerAcceptsItsBoundsAndNothingBeyond)
{
  const P::Integer p(6, 1000);
  for (const char *ok : {"6", "1000", "7", " 7", "7 ", "+7", "07"})
    EXPECT_TRUE(p.match(ok)) << ok;
  for (const char *bad : {"5", "1001", "-3", "7.0", "1e2", "0x10", "", " ", "7 8", "seven",
                          "2147483648"})
    EXPECT_FALSE(p.match(bad)) << bad;
}

TEST(Patterns, DoubleAcceptsItsBoundsAndNothingBeyond)
{
  const P::Double p(0.05, 100.0);
  for (const char *ok : {"0.05", "100", "1e2", "5e-2", " 2", "2 ", ".5", "5.", "+3"})
    EXPECT_TRUE(p.match(ok)) << ok;
  for (const char *bad : {"0.0499999", "100.000001", "-1", "1.5.3", "1,5", "", "1e", "nan", "inf",
                          "1e400", "3 mm"})
    EXPECT_FALSE(p.match(bad)) << bad;
}

TEST(Patterns, BoolIsTrueOrFalseOnly)
{
  const P::Bool p;
  EXPECT_TRUE(p.match("true"));
  EXPECT_TRUE(p.match("false"));
  for (const char *bad : {"yes", "no", "True", "FALSE", "1", "0", " true", "true ", ""})
    EXPECT_FALSE(p.match(bad)) << bad;
}

TEST(Patterns, SelectionMatchesOneChoiceExactly)
{
  const P::Selection p("linear|parabolic|hunt-crossley");
  for (const char *ok : {"linear", "parabolic", "hunt-crossley"})
    EXPECT_TRUE(p.match(ok)) << ok;
  for (const char *bad :
       {"", "line", "linearx", " linear", "linear ", "Linear", "linear|parabolic"})
    EXPECT_FALSE(p.match(bad)) << bad;
}

TEST(Patterns, AnythingMatchesAnyText)
{
  EXPECT_TRUE(P::Anything().match(""));
  EXPECT_TRUE(P::Anything().match("a b/c.json"));
}

TEST(Patterns, ListChecksItsLengthAndEveryElement)
{
  const P::List p(P::Double(0, 10), 0, 3, ",");
  for (const char *ok : {"", " ", "1", "1,2,3", "1, 2 ,3", " 1 , 2 ", "0, 10", "1,"})
    EXPECT_TRUE(p.match(ok)) << ok;
  for (const char *bad : {"1,2,3,4", "1,,2", ",1", "11", "-1", "1;2"})
    EXPECT_FALSE(p.match(bad)) << bad;
  const P::List at_least_one(P::Double(0, 10), 1, 2, ",");
  EXPECT_FALSE(at_least_one.match(""));
  EXPECT_TRUE(at_least_one.match("4"));
  EXPECT_EQ(P::split_list(" 1 , 2,", ","), (std::vector<std::string>{"1", "2"}));
}

TEST(ParameterFile, ValuesAreConvertedAndAssigned)
{
  // Requirement: reading a file assigns each bound variable the converted value; comments,
  // blank lines, tabs, upper-case keywords and CR LF line ends are accepted.
  const Values v = parsed("# a scene\r\n"
                          "\r\n"
                          "SUBSECTION Gear pair\r\n"
                          "  subsection Pinion # the driving gear\n"
                          "\tset\tteeth = 07 # seven\n"
                          "    SET module_mm=2.5\n"
                          "    set tip_relief_shape = parabolic\n"
                          "  END\n"
                          "end\n"
                          "subsection Stiffness\n"
                          "  set table_file = \n"
                          "  subsection Fourier\n"
                          "    set amplitudes_N_per_m = 1e6, 2e6\n"
                          "  end\n"
                          "end\n"
                          "subsection Sweep\n"
                          "  set enabled = true\n"
                          "end\n");
  EXPECT_EQ(v.teeth, 7);
  EXPECT_DOUBLE_EQ(v.module_mm, 2.5);
  EXPECT_EQ(v.shape, "parabolic");
  EXPECT_EQ(v.file, "");
  EXPECT_EQ(v.amplitudes, (std::vector<double>{1e6, 2e6}));
  EXPECT_TRUE(v.enabled);
}

// Requirement: an unknown key or subsection is refused with the source, the line and the name
// that is not declared, and the subsection it was looked for in.
TEST(ParameterFileErrors, UnknownKeyOrSubsectionNamesSourceLineAndName)
{
  struct Case
  {
    const char              *text, *source;
    std::vector<std::string> expected;
  };
  const Case cases[] = {
    {"subsection Sweep\n  set enabled = true\n  set enabledd = true\nend\n", "unknown_key.prm",
     {"unknown_key.prm, line 3", "\"enabledd\"", "subsection \"Sweep\""}},
    {"subsection Gear pair\n  subsection Pinionn\n  end\nend\n", "scene.prm",
     {"scene.prm, line 2", "\"Pinionn\"", "\"Gear pair\""}}};
  for (const auto &c : cases)
    {
      const std::string e = parse_error(c.text, c.source);
      for (const auto &expected : c.expected)
        EXPECT_THAT(e, HasSubstr(expected)) << c.text;
    }
}

TEST(ParameterFileErrors, RefusedValueNamesLineKeyValueAndPattern)
{
  const std::string range = parse_error("subsection Gear pair\n"
                                        "  subsection Pinion\n"
                                        "    set teeth = 5\n"
                                        "  end\n"
                                        "end\n");
  EXPECT_THAT(range, HasSubstr("scene.prm, line 3"));
  EXPECT_THAT(range, HasSubstr("Gear pair/Pinion/teeth = \"5\""));
  EXPECT_THAT(range, HasSubstr("[Integer range 6...1000 (inclusive)]"));
  const std::string number = parse_error("subsection Sweep\n"
                                         "  set damping_ratio = 1.5.3\n"
                                         "end\n");
  EXPECT_THAT(number, HasSubstr("line 2"));
  EXPECT_THAT(number, HasSubstr("damping_ratio"));
  EXPECT_THAT(number, HasSubstr("1.5.3"));
  EXPECT_THAT(parse_error("subsection Sweep\n  set enabled = yes\nend\n"), HasSubstr("[Bool]"));
  EXPECT_THAT(parse_error("subsection Sweep\n  set enabled\nend\n"), HasSubstr("line 2"));
  EXPECT_THAT(parse_error("subsection Sweep\n  enabled = true\nend\n"),
              HasSubstr("line 2: cannot read \"enabled = true\""));
}

TEST(ParameterFileErrors, KeySetTwiceInOneFileNamesBothLines)
{
  // Requirement: a key set twice in one file is a mistake (which one did the author mean?), not
  // a silent override; the same key in different subsections is fine.
  const std::string e = parse_error("subsection Sweep\n"
                                    "  set damping_ratio = 0.1\n"
                                    "  set enabled = true\n"
                                    "  set damping_ratio = 0.2\n"
                                    "end\n");
  EXPECT_THAT(e, HasSubstr("line 4"));
  EXPECT_THAT(e, HasSubstr("Sweep/damping_ratio is set twice, on lines 2 and 4"));
  // Also when the subsection is entered again.
  EXPECT_THAT(parse_error("subsection Sweep\n  set enabled = true\nend\n"
                          "subsection Sweep\n  set enabled = false\nend\n"),
              HasSubstr("on lines 2 and 5"));
  // set() after reading a file overrides (the command line's --set).
  Values        v;
  ParameterFile prm;
  declare(prm, v);
  std::istringstream in("subsection Sweep\n  set damping_ratio = 0.1\nend\n");
  prm.parse(in, "a.prm");
  prm.set("Sweep", "damping_ratio", "0.2");
  prm.set("Sweep", "damping_ratio", "0.3");
  EXPECT_DOUBLE_EQ(v.ratio, 0.3);
}

TEST(ParameterFileErrors, UnbalancedSubsectionsAreRefused)
{
  // An end without an open subsection.
  EXPECT_THAT(parse_error("subsection Sweep\n  set enabled = true\nend\nend\n"),
              HasSubstr("scene.prm, line 4: \"end\" without an open subsection"));
  EXPECT_THAT(parse_error("end\n"), HasSubstr("line 1"));
  // A subsection without its end: named with the line that opened it.
  const std::string missing = parse_error("subsection Sweep\n"
                                          "  set enabled = true\n"
                                          "end\n"
                                          "subsection Gear pair\n"
                                          "  subsection Pinion\n"
                                          "  end\n");
  EXPECT_THAT(missing, HasSubstr("scene.prm, line 4: subsection \"Gear pair\" is not closed"));
  EXPECT_THAT(parse_error("subsection Gear pair\n  subsection Pinion\n"),
              HasSubstr("line 2: subsection \"Gear pair/Pinion\" is not closed"));
  EXPECT_THAT(parse_error("subsection Sweep\nend Sweep\n"), HasSubstr("line 2"));
}

TEST(ParameterFileErrors, ControlCharactersAreRefused)
{
  // Requirement: a value with a control character (other than tab) is refused, in a file and
  // from set(), naming the character.
  EXPECT_THAT(parse_error("subsection Stiffness\n  set table_file = a\vb\nend\n"),
              HasSubstr("line 2: control character 0x0b"));
  EXPECT_THAT(parse_error("subsection Stiffness\n  set table_file = a\rb\nend\n"),
              HasSubstr("0x0d"));
  EXPECT_EQ(parsed("subsection Stiffness\n  set table_file = a\tb\nend\n").file, "a b");
  Values        v;
  ParameterFile prm;
  declare(prm, v);
  try
    {
      prm.set("Stiffness", "table_file", "a\nb");
      FAIL() << "a newline in a value was accepted";
    }
  catch (const ParameterFileError &e)
    {
      EXPECT_THAT(e.what(), HasSubstr("Stiffness/table_file"));
      EXPECT_THAT(e.what(), HasSubstr("0x0a"));
    }
  // A '#' would start a comment when the value is printed and read again.
  EXPECT_THROW(prm.set("Stiffness", "table_file", "a#b"), ParameterFileError);
  EXPECT_EQ(v.file, "");
}

TEST(ParameterFileErrors, ContinuationLinesAreRefused)
{
  // Requirement: no scene uses continuation lines; a trailing backslash is refused with a clear
  // message instead of silently joining the next line (also in a comment).
  const std::string e = parse_error("subsection Sweep\n  set damping_ratio = 0.1 \\\n  2\nend\n");
  EXPECT_THAT(e, HasSubstr("line 2: the line ends in a backslash"));
  EXPECT_THAT(e, HasSubstr("continuation lines are not supported"));
  EXPECT_THAT(parse_error("# comment \\\nsubsection Sweep\nend\n"), HasSubstr("line 1"));
}

TEST(ParameterFileErrors, SetNamesTheEntryAndThePattern)
{
  Values        v;
  ParameterFile prm;
  declare(prm, v);
  try
    {
      prm.set("Gear pair/Pinion", "teeth", "5");
      FAIL();
    }
  catch (const ParameterFileError &e)
    {
      EXPECT_EQ(std::string(e.what()), "Gear pair/Pinion/teeth = \"5\" is not allowed; allowed: "
                                       "[Integer range 6...1000 (inclusive)]");
    }
  EXPECT_EQ(v.teeth, 23);
  EXPECT_THROW(prm.set("Gear pair/Pinion", "teeths", "7"), ParameterFileError);
  EXPECT_THROW(prm.set("Gear pair/Pinionn", "teeth", "7"), ParameterFileError);
  EXPECT_EQ(prm.find("Gear pair/Pinion", "teeth")->text(), "23");
  EXPECT_EQ(prm.find("Gear pair", "teeth"), nullptr);
}

TEST(ParameterFile, DeclarationMistakesAreProgrammingErrors)
{
  int           n = 3, m = 0;
  ParameterFile prm;
  EXPECT_THROW(prm.add("n", n, P::Integer(0, 10), ""), std::logic_error); // no help text
  EXPECT_THROW(prm.add("n", n, P::Integer(5, 10), "n"), std::logic_error); // default refused
  prm.add("n", n, P::Integer(0, 10), "n");
  EXPECT_THROW(prm.add("n", m, P::Integer(0, 10), "n"), std::logic_error); // twice
  EXPECT_THROW(prm.leave_subsection(), std::logic_error);
  std::vector<double> list;
  EXPECT_THROW(prm.add("l", list, P::Double(0, 1), "l"), std::logic_error); // not a list
}

TEST(ParameterFile, DocumentedFormIsTheParameterFileLayout)
{
  // Requirement: help texts as comments wrapped at 78 columns, `set` lines aligned per
  // subsection, a blank line between entries, nested subsections indented by two spaces, two
  // blank lines after a top-level `end`, and "# default:" where a value differs.
  Values        v;
  ParameterFile prm;
  declare(prm, v);
  prm.set("Sweep", "damping_ratio", "0.1");
  EXPECT_EQ(prm.print(ParameterFile::Style::documented),
            "# Listing of Parameters\n"
            "# ---------------------\n"
            "subsection Gear pair\n"
            "  subsection Pinion\n"
            "    # Number of teeth (count).\n"
            "    set teeth            = 23\n"
            "\n"
            "    # Normal module m [mm].\n"
            "    set module_mm        = 3\n"
            "\n"
            "    # Shape of the tip relief along the roll length: linear or parabolic.\n"
            "    set tip_relief_shape = linear\n"
            "  end\n"
            "\n"
            "end\n"
            "\n"
            "\n"
            "subsection Stiffness\n"
            "  # Mean stiffness [N/m].\n"
            "  set k_mean_N_per_m = 4.17e+08\n"
            "\n"
            "  # Stiffness JSON file.\n"
            "  set table_file     = \n"
            "\n"
            "\n"
            "  subsection Fourier\n"
            "    # Harmonic amplitudes [N/m], comma separated.\n"
            "    set amplitudes_N_per_m = \n"
            "  end\n"
            "\n"
            "end\n"
            "\n"
            "\n"
            "subsection Sweep\n"
            "  # Whether the sweep runs (true/false).\n"
            "  set enabled       = false\n"
            "\n"
            "  # Damping ratio [dimensionless].\n"
            "  set damping_ratio = 0.1   # default: 0.015\n"
            "end\n"
            "\n"
            "\n");
  EXPECT_EQ(prm.print(ParameterFile::Style::short_form, ParameterFile::Order::alphabetical),
            "subsection Gear pair\n"
            "  subsection Pinion\n"
            "    set module_mm        = 3\n"
            "    set teeth            = 23\n"
            "    set tip_relief_shape = linear\n"
            "  end\n"
            "end\n"
            "subsection Stiffness\n"
            "  set k_mean_N_per_m = 4.17e+08\n"
            "  set table_file     = \n"
            "  subsection Fourier\n"
            "    set amplitudes_N_per_m = \n"
            "  end\n"
            "end\n"
            "subsection Sweep\n"
            "  set damping_ratio = 0.1\n"
            "  set enabled       = false\n"
            "end\n");
}

TEST(ParameterFile, OmittedEntriesLeaveNoTraceInThePrintedForm)
{
  // Requirement: an entry that `omit` holds for is left out, and the columns of its subsection are
  // aligned as if it had never been declared (a hash over the form is the one of a file without
  // it); the other subsections print as without `omit`.
  Values        v;
  ParameterFile prm;
  declare(prm, v);
  const auto        alphabetical = ParameterFile::Order::alphabetical;
  const std::string full         = prm.print(ParameterFile::Style::short_form, alphabetical);
  EXPECT_EQ(prm.print(ParameterFile::Style::short_form, alphabetical,
                      [](const ParameterFile::Entry &e) {
                        return e.section() == "Gear pair/Pinion" && e.key() == "tip_relief_shape";
                      }),
            "subsection Gear pair\n"
            "  subsection Pinion\n"
            "    set module_mm = 3\n"
            "    set teeth     = 23\n"
            "  end\n"
            "end\n" +
              full.substr(full.find("subsection Stiffness")));
}

TEST(ParameterFile, LongHelpTextsWrapAtWordsWithinSeventyEightColumns)
{
  int           n = 1;
  ParameterFile prm;
  prm.enter_subsection("A");
  prm.add("n", n, P::Integer(0, 10),
          "Iteration cap of the active-set contact solver per solve (count); reaching it is a "
          "numerical failure (exit 3) with the history of the active set, and "
          "averyveryveryveryveryveryveryveryveryveryveryveryveryveryveryveryveryverylongword.");
  prm.leave_subsection();
  EXPECT_EQ(prm.print(ParameterFile::Style::documented),
            "# Listing of Parameters\n"
            "# ---------------------\n"
            "subsection A\n"
            "  # Iteration cap of the active-set contact solver per solve (count); reaching\n"
            "  # it is a numerical failure (exit 3) with the history of the active set, and\n"
            "  # averyveryveryveryveryveryveryveryveryveryveryveryveryveryveryveryveryverylongword.\n"
            "  set n = 1\n"
            "end\n"
            "\n"
            "\n");
}

TEST(ParameterFileErrors, ValuesLongerThanTheLimitAreRefusedNamingTheKeyAndTheLength)
{
  // Requirement: a value of at most ParameterFile::max_value_length characters is read; a longer
  // one is refused before its pattern is checked or it is converted, naming the key and the
  // length, without the value itself (the message stays under 1 kB for a value of megabytes).
  const std::string at_limit(ParameterFile::max_value_length, 'a');
  Values            v;
  ParameterFile     prm;
  declare(prm, v);
  prm.set("Stiffness", "table_file", at_limit);
  EXPECT_EQ(v.file, at_limit);
  const std::string err = parse_error("subsection Sweep\n  set damping_ratio = " +
                                      std::string(5u << 20, '1') + "\nend\n");
  EXPECT_THAT(err, HasSubstr("scene.prm, line 2: Sweep/damping_ratio: the value is 5242880 "
                             "characters long, more than the 16384"));
  EXPECT_LT(err.size(), 1000u);
  const std::string json_err = [] {
    Values        w;
    ParameterFile p;
    declare(p, w);
    try
      {
        p.parse_json(nlohmann::json{{"Sweep", {{"damping_ratio", std::string(20000, '1')}}}}, "s.json");
      }
    catch (const ParameterFileError &e)
      {
        return std::string(e.what());
      }
    return std::string("(no error)");
  }();
  EXPECT_THAT(json_err, HasSubstr("\"damping_ratio\": the value is 20000 characters long"));
}

TEST(ParameterFileErrors, MessagesQuoteLongValuesCut)
{
  // Requirement: messages quote a value (or a line) by its first 60 characters and its length,
  // with bytes that are no text as \xNN (common/shown_text.h).
  const std::string err = parse_error("subsection Gear pair\n subsection Pinion\n  set tip_relief_shape = " +
                                      std::string(10000, 'q') + "\n end\nend\n");
  EXPECT_THAT(err, HasSubstr("tip_relief_shape = \"" + std::string(60, 'q') + "... (10000 characters)\""));
  EXPECT_LT(err.size(), 300u);
  EXPECT_EQ(shown("ab\001c"), "ab\\x01c");
  EXPECT_EQ(shown(std::string(61, 'z'), 60), std::string(60, 'z') + "... (61 characters)");
  EXPECT_EQ(shown(std::string(60, 'z'), 60), std::string(60, 'z'));
}

TEST(JsonFiles, NestingIsMeasuredWithoutConversionAndBoundedOnReading)
{
  // Requirement: the nesting depth of JSON text is counted by a scan (brackets inside strings do
  // not count), and read_json_file refuses a file nested deeper than max_json_nesting naming the
  // depth, before the text is parsed (100 000 levels end with an InputError, not a crash).
  EXPECT_EQ(json_nesting_depth("1"), 0u);
  EXPECT_EQ(json_nesting_depth(R"({"a": [1, {"b": "[[[{{{\"]]"}]})"), 3u);
  const fs::path dir = fs::temp_directory_path() / ("hg_json_depth_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path deep = dir / "deep.json";
  std::ofstream(deep) << std::string(100000, '[') << std::string(100000, ']');
  try
    {
      read_json_file(deep, "scene file");
      ADD_FAILURE() << "not refused";
    }
  catch (const InputError &e)
    {
      EXPECT_THAT(e.what(), HasSubstr("nested 100000 levels deep, more than the 64 levels"));
    }
  const fs::path fine = dir / "fine.json";
  std::string    text = std::string(max_json_nesting, '[') + std::string(max_json_nesting, ']');
  std::ofstream(fine) << text;
  EXPECT_NO_THROW(read_json_file(fine, "scene file"));
  fs::remove_all(dir);
}
