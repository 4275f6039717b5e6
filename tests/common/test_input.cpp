// Typed TOML reading: values, ranges, choices, unknown keys, and that every error names file:line:column
// and the dotted key path. Line and column numbers are counted by hand in the texts below (1-based).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "common/input.hpp"

namespace nvh::input {
namespace {

// Substring check with a readable failure message (gtest only, no gmock).
::testing::AssertionResult Contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "\"" << text << "\" does not contain \"" << part << "\"";
}

// Run `f`, expect an nvh::Error, and return it.
template <typename F>
Error expect_error(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "expected nvh::Error, nothing was thrown";
  return Error("nothing thrown");
}

void expect_at(const Error& e, int line, int column, const std::string& key) {
  EXPECT_EQ(e.where().file, "test.toml") << e.what();
  EXPECT_EQ(e.where().line, line) << e.what();
  EXPECT_EQ(e.where().column, column) << e.what();
  EXPECT_EQ(e.key(), key) << e.what();
  const std::string prefix = "test.toml:" + std::to_string(line) + ":" + std::to_string(column) + ": ";
  EXPECT_EQ(std::string(e.what()).rfind(prefix, 0), 0u) << e.what();
  if (!key.empty()) {
    EXPECT_TRUE(Contains(e.what(), "'" + key + "'"));
  }
}

TEST(Input, ReadsScalarsArraysAndIntegersAsNumbers) {
  const auto doc = Document::parse(
      "title = \"crank\"\n"                // 1
      "[beam]\n"                           // 2
      "A = 3\n"                            // 3  integer accepted as a number
      "E = 2.1e11\n"                       // 4
      "n = 12\n"                           // 5
      "lumped = true\n"                    // 6
      "p = [0, 1.5, -2]\n"                 // 7
      "f = [10, 20.5]\n"                   // 8
      "ids = [1, 2, 3]\n"                  // 9
      "names = [\"a\", \"b\"]\n"           // 10
      "pts = [[0, 0, 0], [1, 2, 3.5]]\n",  // 11
      "test.toml");
  EXPECT_EQ(doc.file_name(), "test.toml");
  const Table root = doc.root();
  EXPECT_EQ(root.path(), "");
  EXPECT_EQ(root.string("title"), "crank");
  const Table beam = root.table("beam");
  EXPECT_EQ(beam.path(), "beam");
  EXPECT_DOUBLE_EQ(beam.number("A", Range::positive()), 3.0);
  EXPECT_DOUBLE_EQ(beam.number("E"), 2.1e11);
  EXPECT_EQ(beam.integer("n", Range::at_least(1)), 12);
  EXPECT_TRUE(beam.boolean("lumped"));
  EXPECT_EQ(beam.vec3("p"), (std::array<double, 3>{0.0, 1.5, -2.0}));
  EXPECT_EQ(beam.numbers("f"), (std::vector<double>{10.0, 20.5}));
  EXPECT_EQ(beam.integers("ids"), (std::vector<std::int64_t>{1, 2, 3}));
  EXPECT_EQ(beam.strings("names"), (std::vector<std::string>{"a", "b"}));
  const auto pts = beam.vec3_list("pts");
  ASSERT_EQ(pts.size(), 2u);
  EXPECT_EQ(pts[1], (std::array<double, 3>{1.0, 2.0, 3.5}));

  EXPECT_FALSE(beam.optional_number("rho").has_value());
  EXPECT_DOUBLE_EQ(beam.number_or("rho", 7850.0), 7850.0);
  EXPECT_DOUBLE_EQ(beam.number_or("A", 1.0), 3.0);
  EXPECT_FALSE(beam.optional_integer("m").has_value());
  EXPECT_FALSE(beam.optional_boolean("b").has_value());
  EXPECT_FALSE(beam.optional_string("s").has_value());
  EXPECT_FALSE(beam.optional_vec3("q").has_value());
  EXPECT_FALSE(beam.optional_table("t").has_value());
  EXPECT_FALSE(beam.optional_choice("c", {"x", "y"}).has_value());
  EXPECT_TRUE(beam.table_array("section").empty());
  EXPECT_EQ(beam.optional_vec3("p").value()[2], -2.0);

  EXPECT_TRUE(beam.has("A"));
  EXPECT_FALSE(beam.has("B"));
  EXPECT_EQ(beam.location("E").line, 4);
  EXPECT_EQ(beam.location("E").column, 5);
  EXPECT_EQ(beam.location().line, 2);     // the [beam] header
  EXPECT_EQ(beam.location("B").line, 2);  // missing key: the table
  EXPECT_NO_THROW(beam.finish());
  EXPECT_NO_THROW(root.finish());
}

TEST(Input, NumberOutOfRangeNamesFileLineColumnAndKey) {
  const auto doc = Document::parse(
      "[beam]\n"        // 1
      "A = -0.0031\n"   // 2  value at column 5
      "B = \"abc\"\n",  // 3
      "test.toml");
  const Table beam = doc.root().table("beam");
  Error e = expect_error([&] { beam.number("A", Range::positive()); });
  expect_at(e, 2, 5, "beam.A");
  EXPECT_EQ(e.message(), "expected a number > 0, got -0.0031");

  e = expect_error([&] { beam.number("B"); });
  expect_at(e, 3, 5, "beam.B");
  EXPECT_EQ(e.message(), "expected a number, got a string \"abc\"");

  e = expect_error([&] { beam.optional_number("B", Range::positive()); });
  EXPECT_EQ(e.message(), "expected a number > 0, got a string \"abc\"");
}

TEST(Input, MissingRequiredKeyPointsAtTheTable) {
  const auto doc = Document::parse(
      "# a comment\n"            // 1
      "\n"                       // 2
      "[damping]\n"              // 3
      "model = \"rayleigh\"\n",  // 4
      "test.toml");
  const Table damping = doc.root().table("damping");
  const Error e = expect_error([&] { damping.number("zeta", Range{0.0, 0.5, false, true}); });
  expect_at(e, 3, 1, "damping.zeta");
  EXPECT_EQ(e.message(), "missing required key (expected a number in [0, 0.5))");

  const Error t = expect_error([&] { doc.root().table("beam"); });
  EXPECT_TRUE(Contains(t.message(), "missing required key (expected a table [beam])"));
  // the root has no header: its location is its first key (here the [damping] table)
  EXPECT_EQ(t.where().line, 3);
}

TEST(Input, RangesWithOpenAndClosedEnds) {
  EXPECT_EQ(Range{}.describe(), "a number");
  EXPECT_EQ(Range::positive().describe(), "a number > 0");
  EXPECT_EQ(Range::non_negative().describe(), "a number >= 0");
  EXPECT_EQ(Range::at_least(2).describe(), "a number >= 2");
  EXPECT_EQ(Range::open(0, 1).describe(), "a number in (0, 1)");
  EXPECT_EQ(Range::closed(-1, 2.5).describe(), "a number in [-1, 2.5]");
  EXPECT_EQ((Range{0.0, 0.5, false, true}).describe(), "a number in [0, 0.5)");
  EXPECT_EQ((Range{-std::numeric_limits<double>::infinity(), 3.0, false, true}).describe(), "a number < 3");

  EXPECT_FALSE(Range::positive().contains(0.0));
  EXPECT_TRUE(Range::non_negative().contains(0.0));
  EXPECT_FALSE(Range::open(0, 1).contains(1.0));
  EXPECT_TRUE(Range::closed(0, 1).contains(1.0));
  EXPECT_TRUE(Range::closed(0, 1).contains(0.0));
  EXPECT_FALSE(Range{}.contains(std::numeric_limits<double>::quiet_NaN()));

  const auto doc = Document::parse(
      "lo = 0\n"      // 1
      "hi = 0.5\n"    // 2
      "mid = 0.25\n"  // 3
      "n = 0\n",      // 4
      "test.toml");
  const Table root = doc.root();
  const Range half_open{0.0, 0.5, false, true};
  EXPECT_DOUBLE_EQ(root.number("lo", half_open), 0.0);  // closed lower end
  EXPECT_DOUBLE_EQ(root.number("mid", Range::open(0, 0.5)), 0.25);
  Error e = expect_error([&] { root.number("hi", half_open); });  // open upper end
  expect_at(e, 2, 6, "hi");
  EXPECT_EQ(e.message(), "expected a number in [0, 0.5), got 0.5");
  e = expect_error([&] { root.number("lo", Range::open(0, 1)); });
  expect_at(e, 1, 6, "lo");
  EXPECT_EQ(e.message(), "expected a number in (0, 1), got 0");
  e = expect_error([&] { root.integer("n", Range::at_least(1)); });
  expect_at(e, 4, 5, "n");
  EXPECT_EQ(e.message(), "expected an integer >= 1, got 0");
  e = expect_error([&] { root.integer("mid"); });
  EXPECT_EQ(e.message(), "expected an integer, got a number 0.25");
}

// Issue 18 item 4: every range is finite by default; +-inf, NaN and subnormal numbers are refused by every
// getter (ranged or not), with file, line, column and key.
TEST(Input, NumbersMustBeFiniteEverywhere) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(Range{}.contains(inf));
  EXPECT_FALSE(Range{}.contains(-inf));
  EXPECT_FALSE(Range::positive().contains(inf));
  EXPECT_FALSE(Range::at_least(0).contains(inf));
  EXPECT_FALSE(Range::positive().contains(1e-320));  // subnormal
  EXPECT_FALSE(Range{}.contains(-4e-324));
  EXPECT_TRUE(Range{}.contains(0.0));
  EXPECT_TRUE(Range{}.contains(std::numeric_limits<double>::min()));
  EXPECT_TRUE(Range{}.contains(std::numeric_limits<double>::max()));
  EXPECT_TRUE(Range::positive().allow_infinite().contains(inf));
  EXPECT_FALSE(Range::positive().allow_infinite().contains(-inf));  // still the bounds
  EXPECT_FALSE(Range{}.allow_infinite().contains(std::numeric_limits<double>::quiet_NaN()));
  EXPECT_TRUE(Range::magnitude(2).contains(-2.0));
  EXPECT_FALSE(Range::magnitude(2).contains(2.5));
  EXPECT_EQ(Range::at_most(3).describe(), "a number <= 3");

  const auto doc = Document::parse(
      "a = inf\n"                         // 1
      "b = -inf\n"                        // 2
      "c = nan\n"                         // 3
      "d = 1e-320\n"                      // 4
      "at = [0, 0, inf]\n"                // 5  inf at column 13
      "list = [1.0, -inf]\n"              // 6  -inf at column 14
      "rows = [[0, 1], [nan, 2]]\n"       // 7  nan at column 18
      "pts = [[0, 0, 0], [1, inf, 0]]\n"  // 8  inf at column 23
      "[t]\n"                             // 9
      "x = +inf\n",                       // 10
      "test.toml");
  const Table root = doc.root();
  Error e = expect_error([&] { root.number("a"); });
  expect_at(e, 1, 5, "a");
  EXPECT_EQ(e.message(), "expected a number, got inf (numbers must be finite)");
  e = expect_error([&] { root.number("b", Range::at_least(-1e9)); });
  expect_at(e, 2, 5, "b");
  EXPECT_EQ(e.message(), "expected a number >= -1e+09, got -inf (numbers must be finite)");
  e = expect_error([&] { root.optional_number("c", Range::non_negative()); });
  expect_at(e, 3, 5, "c");
  EXPECT_TRUE(Contains(e.message(), "numbers must be finite"));
  e = expect_error([&] { root.number_or("d", 1.0, Range::positive()); });
  expect_at(e, 4, 5, "d");
  EXPECT_TRUE(Contains(e.message(), "got 1e-320 (a subnormal number"));
  e = expect_error([&] { root.vec3("at"); });
  expect_at(e, 5, 13, "at[3]");
  EXPECT_EQ(e.message(), "expected a number, got inf (numbers must be finite)");
  e = expect_error([&] { root.numbers("list"); });
  expect_at(e, 6, 14, "list[2]");
  e = expect_error([&] { root.number_rows("rows", 2); });
  expect_at(e, 7, 18, "rows[2][1]");
  EXPECT_TRUE(Contains(e.message(), "numbers must be finite"));
  e = expect_error([&] { root.vec3_list("pts"); });
  expect_at(e, 8, 23, "pts[2][2]");
  e = expect_error([&] { root.table("t").optional_vec3("x"); });
  EXPECT_EQ(e.key(), "t.x");
  e = expect_error([&] { root.table("t").number("x", Range::positive()); });
  expect_at(e, 10, 5, "t.x");
  // Where a key allows infinity, the bounds still apply.
  EXPECT_EQ(root.table("t").number("x", Range::positive().allow_infinite()), inf);
}

// Issue 18 item 3: deep nesting overflowed toml11's recursive parser (a crash) and long lines took quadratic
// time; both are refused before toml11 sees the text, naming the file and line.
TEST(Input, DeepNestingIsRefusedBeforeParsing) {
  const int deep = 6000;
  const std::string arrays = "# nested\na = " + std::string(deep, '[') + std::string(deep, ']') + "\n";
  Error e = expect_error([&] { Document::parse(arrays, "test.toml"); });
  expect_at(e, 2, 5 + kMaxNesting, "");
  EXPECT_TRUE(Contains(e.message(), "nested deeper than 64 levels"));

  std::string tables = "b = ";
  for (int i = 0; i < deep; ++i) tables += "{x = ";
  tables += "1" + std::string(deep, '}') + "\n";
  e = expect_error([&] { Document::parse(tables, "test.toml"); });
  EXPECT_EQ(e.where().line, 1) << e.what();
  EXPECT_TRUE(Contains(e.message(), "nested deeper than 64 levels"));

  std::string dotted = "c";
  for (int i = 0; i < 100000; ++i) dotted += ".d";
  e = expect_error([&] { Document::parse("x = 1\n" + dotted + " = 1\n", "test.toml"); });
  EXPECT_EQ(e.where().line, 2) << e.what();
  EXPECT_TRUE(Contains(e.message(), "a dotted key of more than 64 parts"));
  e = expect_error([&] { Document::parse("x = 1\n[" + dotted + "]\ny = 2\n", "test.toml"); });
  EXPECT_EQ(e.where().line, 2) << e.what();
  EXPECT_TRUE(Contains(e.message(), "a dotted key of more than 64 parts"));

  // At the limits, and with brackets, braces and dots in strings and comments, files parse as before.
  const std::string ok = "a = " + std::string(kMaxNesting, '[') + std::string(kMaxNesting, ']') + "\n" +
                         "s = \"[[[[{{{{ a.b.c \\\" [[[\"\n"
                         "l = '[[[[{{{{'\n"
                         "m = \"\"\"\n[[[[\n\\\"\"\" {{{{ \"\"\"\"\"\n"
                         "n = '''\n{{{{''''\n"
                         "# [[[[[[[[ {{{{{{ a.b.c.d\n"
                         "v = 1.5\n"
                         "t = [{ a.b = 1.25, c = [1.5, 2.5] }, {}]\n"
                         "[\"q.r\".s]\n"
                         "w = { \"x.y\" = 2 }\n";
  const auto doc = Document::parse(ok, "test.toml");
  EXPECT_EQ(doc.root().string("s"), "[[[[{{{{ a.b.c \" [[[");
  EXPECT_EQ(doc.root().string("m"), "[[[[\n\"\"\" {{{{ \"\"");
  EXPECT_EQ(doc.root().string("n"), "{{{{'");
  EXPECT_DOUBLE_EQ(doc.root().number("v"), 1.5);
  EXPECT_EQ(doc.root().table("q.r").table("s").table("w").number("x.y"), 2.0);
  std::string parts = "k";
  for (int i = 1; i < kMaxNesting; ++i) parts += ".k";
  EXPECT_NO_THROW(Document::parse(parts + " = 1\n", "test.toml"));
  EXPECT_THROW(Document::parse(parts + ".k = 1\n", "test.toml"), Error);
}

TEST(Input, LongLinesAreRefusedBeforeParsing) {
  // 20k numbers on one line (40 KB) are within the limit and parse in well under a second.
  std::string line = "a = [1";
  for (int i = 1; i < 20000; ++i) line += ",1";
  line += "]\n";
  ASSERT_LE(line.size(), kMaxLineLength);
  const auto doc = Document::parse("x = 1\n" + line, "test.toml");
  EXPECT_EQ(doc.root().numbers("a").size(), 20000u);

  std::string longer = "a = [1";
  while (longer.size() <= kMaxLineLength) longer += ", 1";
  longer += "]";
  const Error e = expect_error([&] { Document::parse("x = 1\n\n" + longer + "\n", "test.toml"); });
  expect_at(e, 3, 1, "");
  EXPECT_TRUE(Contains(e.message(), "bytes; the limit is 65536 bytes per line"));
  EXPECT_THROW(Document::parse(longer, "test.toml"), Error);  // the last line, without a newline
}

TEST(Input, OtherTypeMismatches) {
  const auto doc = Document::parse(
      "flag = \"yes\"\n"  // 1
      "name = 3\n"        // 2
      "sub = 1.0\n"       // 3
      "list = 4\n",       // 4
      "test.toml");
  const Table root = doc.root();
  Error e = expect_error([&] { root.boolean("flag"); });
  expect_at(e, 1, 8, "flag");
  EXPECT_EQ(e.message(), "expected a boolean (true or false), got a string \"yes\"");
  e = expect_error([&] { root.string("name"); });
  expect_at(e, 2, 8, "name");
  EXPECT_EQ(e.message(), "expected a string, got an integer 3");
  e = expect_error([&] { root.table("sub"); });
  expect_at(e, 3, 7, "sub");
  EXPECT_EQ(e.message(), "expected a table [sub], got a number 1.0");
  e = expect_error([&] { root.numbers("list"); });
  expect_at(e, 4, 8, "list");
  EXPECT_EQ(e.message(), "expected an array of numbers, got an integer 4");
}

TEST(Input, ChoiceWithDidYouMean) {
  const auto doc = Document::parse(
      "[reduction]\n"         // 1
      "method = \"craig\"\n"  // 2  value at column 10
      "solver = \"Modal\"\n"  // 3
      "other = \"xyz\"\n"     // 4
      "ok = \"guyan\"\n",     // 5
      "test.toml");
  const Table red = doc.root().table("reduction");
  const std::vector<std::string> methods{"modal", "craig-bampton", "guyan"};
  EXPECT_EQ(red.choice("ok", methods), "guyan");
  Error e = expect_error([&] { red.choice("method", methods); });
  expect_at(e, 2, 10, "reduction.method");
  EXPECT_EQ(e.message(),
            "expected one of \"modal\", \"craig-bampton\", \"guyan\", got \"craig\" (did you mean "
            "\"craig-bampton\"?)");
  e = expect_error([&] { red.optional_choice("solver", methods); });
  expect_at(e, 3, 10, "reduction.solver");
  EXPECT_TRUE(Contains(e.message(), "got \"Modal\" (did you mean \"modal\"?)"));
  e = expect_error([&] { red.choice("other", methods); });
  EXPECT_EQ(e.message(), "expected one of \"modal\", \"craig-bampton\", \"guyan\", got \"xyz\"");
  e = expect_error([&] { red.choice("missing", methods); });
  expect_at(e, 1, 1, "reduction.missing");
  EXPECT_EQ(e.message(), "missing required key (expected one of \"modal\", \"craig-bampton\", \"guyan\")");
}

TEST(Input, UnknownKeyWithDidYouMean) {
  const auto doc = Document::parse(
      "[beam]\n"      // 1
      "A = 1.0\n"     // 2
      "Iy = 2.0\n"    // 3
      "Iz = 3.0\n"    // 4
      "J = 4.0\n"     // 5
      "Iyy = 5.0\n"   // 6  value at column 7
      "zzz = 6.0\n",  // 7
      "test.toml");
  const Table beam = doc.root().table("beam");
  for (const char* key : {"A", "Iy", "Iz", "J"}) beam.number(key);
  Error e = expect_error([&] { beam.finish(); });
  expect_at(e, 6, 7, "beam.Iyy");  // the first unknown key in the file
  EXPECT_EQ(e.message(), "unknown key 'Iyy' (did you mean 'Iy'?); accepted keys: A, Iy, Iz, J");

  // Optional getters that found nothing and accept() make keys known too; copies share the record.
  const Table copy = beam;
  copy.optional_number("E");
  copy.accept("Iyy");
  e = expect_error([&] { beam.finish(); });
  expect_at(e, 7, 7, "beam.zzz");
  EXPECT_EQ(e.message(), "unknown key 'zzz'; accepted keys: A, E, Iy, Iyy, Iz, J");
  doc.root().table("beam").accept("zzz");  // another view of the same table shares it as well
  EXPECT_NO_THROW(beam.finish());

  // The root table only knows "beam" once asked for it.
  e = expect_error([&] { Document::parse("[beam]\nA = 1\n", "test.toml").root().finish(); });
  expect_at(e, 1, 1, "beam");
  EXPECT_EQ(e.message(), "unknown key 'beam'; no keys are accepted here");
}

TEST(Input, Vec3LengthAndElements) {
  const auto doc = Document::parse(
      "p = [1.0, 2.0]\n"            // 1
      "q = [1.0, \"x\", 3.0]\n"     // 2  "x" at column 11
      "r = 5\n"                     // 3
      "s = [[0, 0, 0], [1, 2]]\n",  // 4  [1, 2] at column 17
      "test.toml");
  const Table root = doc.root();
  Error e = expect_error([&] { root.vec3("p"); });
  expect_at(e, 1, 5, "p");
  EXPECT_EQ(e.message(), "expected 3 numbers [x, y, z], got 2");
  e = expect_error([&] { root.optional_vec3("q"); });
  expect_at(e, 2, 11, "q[2]");
  EXPECT_EQ(e.message(), "expected a number, got a string \"x\"");
  e = expect_error([&] { root.vec3("r"); });
  EXPECT_EQ(e.message(), "expected 3 numbers [x, y, z], got an integer 5");
  e = expect_error([&] { root.vec3_list("s"); });
  expect_at(e, 4, 17, "s[2]");
  EXPECT_EQ(e.message(), "expected 3 numbers [x, y, z], got 2");
  e = expect_error([&] { root.vec3("missing"); });
  EXPECT_EQ(e.message(), "missing required key (expected 3 numbers [x, y, z])");
}

TEST(Input, ArrayElementsHaveIndexedPaths) {
  const auto doc = Document::parse(
      "f = [10.0, -2.0, 3.0]\n"  // 1  -2.0 at column 12
      "n = [\"a\", 2]\n",        // 2  2 at column 11
      "test.toml");
  const Table root = doc.root();
  Error e = expect_error([&] { root.numbers("f", Range::positive()); });
  expect_at(e, 1, 12, "f[2]");
  EXPECT_EQ(e.message(), "expected a number > 0, got -2.0");
  e = expect_error([&] { root.strings("n"); });
  expect_at(e, 2, 11, "n[2]");
  EXPECT_EQ(e.message(), "expected a string, got an integer 2");
}

TEST(Input, ArraysOfTablesWithIndexPaths) {
  const auto doc = Document::parse(
      "[[beam.section]]\n"  // 1
      "A = 1.0\n"           // 2
      "[[beam.section]]\n"  // 3
      "A = -1.0\n"          // 4  value at column 5
      "Iyy = 2\n"           // 5
      "[[beam.section]]\n"  // 6
      "A = 2.0\n",          // 7
      "test.toml");
  const Table beam = doc.root().table("beam");
  const auto sections = beam.table_array("section");
  ASSERT_EQ(sections.size(), 3u);
  EXPECT_EQ(sections[1].path(), "beam.section[2]");
  EXPECT_EQ(sections[1].location().line, 3);
  EXPECT_DOUBLE_EQ(sections[0].number("A", Range::positive()), 1.0);
  Error e = expect_error([&] { sections[1].number("A", Range::positive()); });
  expect_at(e, 4, 5, "beam.section[2].A");
  EXPECT_EQ(e.message(), "expected a number > 0, got -1.0");
  // A missing key with a misspelt one beside it points at the misspelling.
  e = expect_error([&] { sections[1].number("Iy"); });
  expect_at(e, 5, 7, "beam.section[2].Iy");
  EXPECT_TRUE(Contains(e.message(), "found unknown key 'Iyy' - did you mean 'Iy'?"));
  // Without a near key it points at the table.
  e = expect_error([&] { sections[1].number("Iz"); });
  expect_at(e, 3, 1, "beam.section[2].Iz");
  e = expect_error([&] { sections[1].finish(); });
  expect_at(e, 5, 7, "beam.section[2].Iyy");
  EXPECT_TRUE(Contains(e.message(), "unknown key 'Iyy' (did you mean 'Iy'?)"));
  EXPECT_NO_THROW(beam.finish());
}

TEST(Input, SingleTableWhereArrayOfTablesExpected) {
  const auto doc = Document::parse(
      "[beam.section]\n"        // 1
      "A = 1.0\n"               // 2
      "[beam.other]\n"          // 3
      "list = [1, {B = 2}]\n",  // 4  inline table at column 12
      "test.toml");
  const Table beam = doc.root().table("beam");
  Error e = expect_error([&] { beam.table_array("section"); });
  expect_at(e, 1, 1, "beam.section");
  EXPECT_TRUE(Contains(e.message(), "expected an array of tables [[beam.section]]"));
  e = expect_error([&] { beam.table("other").table_array("list"); });
  expect_at(e, 4, 9, "beam.other.list[1]");
  EXPECT_EQ(e.message(), "expected a table, got an integer 1");
}

TEST(Input, TableKeysInFileOrderAndMarkedKnown) {
  const auto doc = Document::parse(
      "[material.steel]\n"      // 1
      "E = 2.1e11\n"            // 2
      "[material.aluminium]\n"  // 3
      "E = 7e10\n"              // 4
      "[material]\n"            // 5
      "default = \"steel\"\n",  // 6
      "test.toml");
  const Table material = doc.root().table("material");
  EXPECT_EQ(material.table_keys(), (std::vector<std::string>{"steel", "aluminium"}));
  EXPECT_DOUBLE_EQ(material.table("aluminium").number("E"), 7e10);
  Error e = expect_error([&] { material.finish(); });
  expect_at(e, 6, 11, "material.default");
  material.string("default");
  EXPECT_NO_THROW(material.finish());
}

TEST(Input, FailAndAccept) {
  const auto doc = Document::parse(
      "[mesh]\n"        // 1
      "size = 0.01\n",  // 2
      "test.toml");
  const Table mesh = doc.root().table("mesh");
  Error e = expect_error([&] { mesh.fail("size", "too coarse for 2 kHz"); });
  expect_at(e, 2, 8, "mesh.size");
  EXPECT_EQ(e.message(), "too coarse for 2 kHz");
  e = expect_error([&] { mesh.fail("no elements"); });
  expect_at(e, 1, 1, "mesh");
  mesh.accept("size");
  EXPECT_NO_THROW(mesh.finish());
}

TEST(Input, SyntaxErrorsCarryTheLine) {
  Error e = expect_error([] { Document::parse("a = 1\nb = \nc = 3\n", "test.toml"); });
  expect_at(e, 2, 5, "");
  EXPECT_TRUE(Contains(e.message(), "invalid TOML"));

  e = expect_error([] { Document::parse("a = 1\n\n\nb = tru\n", "test.toml"); });
  EXPECT_EQ(e.where().line, 4);
  EXPECT_TRUE(Contains(e.what(), "test.toml:4:"));

  e = expect_error([] { Document::parse("[t]\nq = 1\n[t]\nr = 2\n", "test.toml"); });  // table defined twice
  EXPECT_EQ(e.where().line, 3);
  EXPECT_TRUE(Contains(e.message(), "already exists"));

  e = expect_error([] { Document::parse("x = [1, 2\ny = 1\n", "test.toml"); });
  EXPECT_EQ(e.where().file, "test.toml");
  EXPECT_GE(e.where().line, 1);
  EXPECT_TRUE(Contains(e.what(), "test.toml:"));
}

TEST(Input, MissingFileNamesTheFile) {
  const std::filesystem::path missing =
      std::filesystem::temp_directory_path() / "nvh-no-such-dir" / "crank.toml";
  const Error e = expect_error([&] { Document::load(missing); });
  EXPECT_TRUE(Contains(e.what(), missing.string()));
  EXPECT_TRUE(Contains(e.what(), "cannot open"));
  EXPECT_EQ(e.where().file, missing.string());
}

TEST(Input, LoadsAFile) {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() /
      ("nvh-test-input-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + ".toml");
  {
    std::ofstream out(path);
    out << "[beam]\nA = 1\nB = -1\n";
  }
  const auto doc = Document::load(path);
  EXPECT_EQ(doc.file_name(), path.string());
  const Table beam = doc.root().table("beam");
  EXPECT_DOUBLE_EQ(beam.number("A"), 1.0);
  const Error e = expect_error([&] { beam.number("B", Range::positive()); });
  EXPECT_EQ(e.where().file, path.string());
  EXPECT_EQ(e.where().line, 3);
  std::filesystem::remove(path);
}

TEST(Input, MovedDocumentKeepsTablesValid) {
  auto doc = Document::parse("[a]\nx = 1\n", "test.toml");
  const Table a = doc.root().table("a");
  Document moved = std::move(doc);
  EXPECT_DOUBLE_EQ(a.number("x"), 1.0);
  EXPECT_EQ(moved.root().table("a").number("x"), 1.0);
}

TEST(Input, EditDistanceAndClosest) {
  EXPECT_EQ(edit_distance("", ""), 0u);
  EXPECT_EQ(edit_distance("abc", ""), 3u);
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
  EXPECT_EQ(edit_distance("Iyy", "Iy"), 1u);
  EXPECT_EQ(closest("Iyy", {"A", "Iy", "Iz", "J"}), "Iy");
  EXPECT_EQ(closest("densty", {"density", "E", "nu"}), "density");
  EXPECT_EQ(closest("qqqqqq", {"density", "E", "nu"}), "");
  EXPECT_EQ(closest("x", {"A", "J"}), "");  // a complete rewrite is no suggestion
  EXPECT_EQ(closest("zzz", {"Iz"}), "");
  EXPECT_EQ(closest("MODAL", {"modal"}), "modal");
  EXPECT_EQ(closest("craig", {"modal", "craig-bampton", "guyan"}), "craig-bampton");
  EXPECT_EQ(closest("abc", {}), "");
}

}  // namespace
}  // namespace nvh::input

// A name becomes an HDF5 group in the output (/bodies/NAME, /forces/NAME): "/" would nest groups, a NUL
// would cut the path short, both found by the fuzzer (tests/fuzz) as errors naming "out.h5:/joints/".
TEST(Input, NamesThatWouldBreakAnOutputPathAreRefused) {
  const auto doc = nvh::input::Document::parse(
      "a = \"crank\"\n"
      "b = \"cyl\\u0000inder\"\n"
      "c = \"crank/pin\"\n"
      "d = \"\"\n"
      "e = \"..\"\n"
      "f = \"main bearing 3 (front)\"\n",
      "names.toml");
  const nvh::input::Table t = doc.root();
  EXPECT_EQ(t.name("a"), "crank");
  EXPECT_EQ(t.name("f"), "main bearing 3 (front)");
  for (const char* key : {"b", "c", "d", "e"}) {
    try {
      (void)t.name(key);
      ADD_FAILURE() << key << " was accepted";
    } catch (const nvh::Error& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("names.toml:"), std::string::npos) << m;
      EXPECT_NE(m.find(std::string("'") + key + "'"), std::string::npos) << m;
      EXPECT_NE(m.find("expected a name"), std::string::npos) << m;
    }
  }
}
