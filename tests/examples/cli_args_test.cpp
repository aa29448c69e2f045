// The `ifem` command line's parser (CLI11), generated help, JSON (nlohmann-json) and text
// output, on the tool's own tables.
#include <gtest/gtest.h>
#include <unistd.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "cli.h"
#include "intrinsic/io/mesh_io.h"
#include "json.h"
#include "options.h"
#include "results.h"

namespace ifem::cli {
namespace {

CommandSpec test_spec() {
  CommandSpec spec;
  spec.name = "demo";
  spec.positionals = {"MESH"};
  spec.prose = "A command for tests.\n";
  spec.groups = {
      {"Options",
       {count("k", "K").short_alias('k').at_least(1).defaults_to("10").explain("k"),
        vertex_list("source", "I").explain("ids"),
        real("angle", "A").above(0).at_most(30).defaults_to("25").explain("angle"),
        text("output", "OUT").short_alias('o').mandatory().with_extensions({".ply", ".txt"}),
        flag("fast").explain("go fast")}}};
  return spec;
}

Args parse(const std::vector<std::string>& words) {
  std::vector<const char*> argv;
  for (const std::string& w : words) argv.push_back(w.c_str());
  return Args(test_spec(), static_cast<int>(argv.size()), argv.data());
}

// The message of the UsageError parse() throws ("" when it does not throw).
std::string usage_error(const std::vector<std::string>& words) {
  try {
    parse(words);
  } catch (const UsageError& e) {
    return e.what();
  }
  return "";
}

TEST(Parse, TypedValuesAndDefaults) {
  const Args a =
      parse({"m.obj", "-k", "7", "--source=3,17,42", "--angle", "+12.5", "-o", "x.PLY", "--fast"});
  EXPECT_EQ(a.positional(), std::vector<std::string>{"m.obj"});
  EXPECT_EQ(a.count("k"), 7);
  EXPECT_EQ(a.vertices("source"), (std::vector<Index>{3, 17, 42}));
  EXPECT_DOUBLE_EQ(a.real("angle"), 12.5);
  EXPECT_EQ(a.get("output"), "x.PLY");
  EXPECT_TRUE(a.has("fast"));
  const Args d = parse({"m.obj", "-o", "y.txt"});
  EXPECT_EQ(d.count("k"), 10);
  EXPECT_DOUBLE_EQ(d.real("angle"), 25.0);
  EXPECT_DOUBLE_EQ(d.real_or("angle", 3.0), 3.0);
  EXPECT_TRUE(d.vertices("source").empty());
  EXPECT_NO_THROW(d.check_complete());
}

TEST(Parse, IntegersThatDoNotFitAreErrors) {
  for (const char* v : {"2147483648", "4294967298", "4294967296", "99999999999999999999", "-1", "0",
                        "1e400", "1.5", "nan", "inf", "", "3x", "abc", " 3", "0x10"}) {
    const std::string msg = usage_error({"m.obj", "-k", v, "-o", "x.ply"});
    EXPECT_NE(msg.find("-k '" + std::string(v) + "'"), std::string::npos) << v << ": " << msg;
    EXPECT_NE(msg.find("[1, 2147483647]"), std::string::npos) << v << ": " << msg;
  }
  EXPECT_EQ(parse({"m", "-k", "2147483647", "-o", "x.ply"}).count("k"), 2147483647);
}

TEST(Parse, VertexListsAreCheckedItemByItem) {
  for (const char* v : {"1,4294967296", "-1", "1,,2", ",1", "1,", "", "1;2", "2147483648"}) {
    const std::string msg = usage_error({"m", "--source", v, "-o", "x.ply"});
    EXPECT_NE(msg.find("--source '" + std::string(v) + "'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("vertex ids in [0, 2147483647]"), std::string::npos) << msg;
  }
}

TEST(Parse, RealsMustBeFiniteAndInRange) {
  for (const char* v :
       {"1e400", "-1e400", "nan", "inf", "-inf", "", "abc", "3x", "0", "-1", "30.0001", "0x1p3"}) {
    const std::string msg = usage_error({"m", "--angle", v, "-o", "x.ply"});
    EXPECT_NE(msg.find("--angle '" + std::string(v) + "'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("(0, 30]"), std::string::npos) << v << ": " << msg;
  }
  EXPECT_DOUBLE_EQ(parse({"m", "--angle", "30", "-o", "x.ply"}).real("angle"), 30.0);
}

TEST(Parse, ShapeOfTheCommandLine) {
  EXPECT_NE(usage_error({"m", "--nope"}).find("unknown option --nope"), std::string::npos);
  EXPECT_NE(usage_error({"m", "-x"}).find("unknown option -x"), std::string::npos);
  EXPECT_NE(usage_error({"m", "-o"}).find("--output needs a value"), std::string::npos);
  EXPECT_NE(usage_error({"m", "-o", "--fast"}).find("--output needs a value"), std::string::npos);
  EXPECT_NE(usage_error({"m", "--fast=yes"}).find("--fast takes no value, got 'yes'"),
            std::string::npos);
  EXPECT_NE(usage_error({"m", "-k", "1", "--k=2"}).find("-k given twice"), std::string::npos);
  EXPECT_NE(usage_error({"m", "-o", "x.obj"}).find("must end in .ply or .txt"), std::string::npos);
  EXPECT_NE(usage_error({"m", "-o", ""}).find("empty value"), std::string::npos);
  try {
    parse({"m"}).check_complete();
    FAIL() << "no -o accepted";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("missing -o OUT"), std::string::npos);
  }
  EXPECT_THROW(parse({"a", "b", "-o", "x.ply"}).check_complete(), UsageError);
  // after "--" everything is positional
  EXPECT_EQ(parse({"-o", "x.ply", "--", "-weird.obj"}).positional(),
            std::vector<std::string>{"-weird.obj"});
  EXPECT_TRUE(parse({"--help"}).has("help"));
  EXPECT_TRUE(parse({"-h"}).has("help"));
}

TEST(Parse, InputLimits) {
  const Args a = parse({"m", "--source", "0,5", "-o", "x.ply"});
  EXPECT_NO_THROW(check_input_limits(a, 6, false));
  try {
    check_input_limits(a, 5, false);
    FAIL() << "vertex 5 of 5 accepted";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("--source 5: vertex out of range [0, 5)"),
              std::string::npos)
        << e.what();
  }
}

TEST(Help, ListsEveryOptionOfItsTable) {
  for (const Command& c : all_commands()) {
    const std::string help = render_help(c.spec);
    EXPECT_EQ(help.rfind("usage: ifem " + c.spec.name, 0), 0u) << help;
    for (const OptionGroup& g : c.spec.groups) {
      EXPECT_NE(help.find(g.title + ":\n"), std::string::npos) << c.spec.name;
      for (const OptionSpec& s : g.options) {
        std::string form = s.display();  // "-k", "--output"
        if (s.kind != Kind::kFlag) form += " " + s.placeholder;
        EXPECT_NE(help.find(form), std::string::npos) << c.spec.name << " " << s.name;
        if (!s.default_value.empty()) {
          EXPECT_NE(help.find("default " + s.default_value), std::string::npos) << s.name;
        }
        if (s.kind != Kind::kFlag && (s.kind != Kind::kText || !s.extensions.empty())) {
          EXPECT_NE(help.find(s.describe_range()), std::string::npos) << s.name;
        }
      }
    }
    EXPECT_NE(help.find("-h, --help"), std::string::npos) << c.spec.name;
  }
}

TEST(Help, IsGeneratedFromTheTable) {
  CommandSpec spec = test_spec();
  EXPECT_EQ(render_help(spec).find("--brand-new"), std::string::npos);
  spec.groups[0].options.push_back(
      real("brand-new", "X").at_least(2).defaults_to("3").explain("a new option"));
  const std::string help = render_help(spec);
  EXPECT_NE(help.find("--brand-new X"), std::string::npos) << help;
  EXPECT_NE(help.find("a new option"), std::string::npos);
  EXPECT_NE(help.find("default 3; a finite number in [2, ∞)"), std::string::npos) << help;
  EXPECT_NE(help.find("usage: ifem demo MESH -o OUT [options]"), std::string::npos) << help;
  // and the parser knows it too
  std::vector<const char*> argv = {"m", "-o", "x.ply", "--brand-new", "1"};
  EXPECT_THROW(Args(spec, 5, argv.data()), UsageError);
}

TEST(Tables, DefaultsAreValidValues) {
  for (const Command& c : all_commands()) {
    for (const OptionGroup& g : c.spec.groups) {
      for (const OptionSpec& s : g.options) {
        if (s.default_value.empty()) continue;
        if (s.kind == Kind::kReal) {
          EXPECT_NO_THROW(parse_real(s, s.default_value)) << s.name;
        }
        if (s.kind == Kind::kCount) {
          EXPECT_NO_THROW(parse_integer(s, s.default_value)) << s.name;
        }
      }
    }
  }
}

// `--json` text through nlohmann-json: every string is valid JSON whatever its bytes (the
// hand-written writer's cases; U+FFFD is now written as its UTF-8 bytes, not as "\ufffd", and
// DEL (0x7f) needs no escape in JSON), and each text parses back to the string it stands for.
std::string quoted(const std::string& s) { return json_text(Json(s)); }

TEST(Json, EscapesEverything) {
  const std::string fffd = "\xef\xbf\xbd";  // U+FFFD REPLACEMENT CHARACTER in UTF-8
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"a\"b\\c", "\"a\\\"b\\\\c\""},
      {"\n\t\x01\x7f", "\"\\n\\t\\u0001\x7f\""},
      {"naïve €", "\"naïve €\""},                          // valid UTF-8 kept
      {std::string("a\xff") + "b", "\"a" + fffd + "b\""},  // invalid byte
      {"\xc3", "\"" + fffd + "\""},                        // truncated sequence
      {"\xc0\xaf", "\"" + fffd + fffd + "\""},             // overlong
      {"\xed\xa0\x80", "\"" + fffd + fffd + fffd + "\""},  // surrogate
      {std::string("a\0b", 3), "\"a\\u0000b\""}};
  for (const auto& [in, want] : cases) {
    EXPECT_EQ(quoted(in), want);
    // what a JSON reader gets back: the input where it was UTF-8 (the escaped cases), U+FFFD for
    // each bad byte (the others, whose text is the string itself between its quotes)
    const std::string unquoted = want.substr(1, want.size() - 2);
    const bool escaped = unquoted.find('\\') != std::string::npos;
    EXPECT_EQ(nlohmann::json::parse(quoted(in)).get<std::string>(), escaped ? in : unquoted);
  }
}

TEST(Json, NumbersAndStructure) {
  EXPECT_EQ(json_text(Json(std::numeric_limits<double>::infinity())), "null");
  EXPECT_EQ(json_text(Json(std::nan(""))), "null");
  EXPECT_EQ(json_text(Json(0.1)), "0.1");  // shortest round-trip form
  EXPECT_EQ(json_text(Json(1.0 / 3.0)), "0.3333333333333333");
  Json doc;  // keys in the order they are set, as `ifem info --json` prints them
  doc["n"] = 3;
  doc["x"] = 1.5;
  doc["list"] = {"a", nullptr, true};
  doc["inf"] = 1e308 * 10;
  EXPECT_EQ(json_text(doc),
            "{\n  \"n\": 3,\n  \"x\": 1.5,\n  \"list\": [\n    \"a\",\n    null,\n    true\n  ],\n"
            "  \"inf\": null\n}");
}

// Text outputs (.txt of distance / poisson / eigen, --sources-batch matrices, tangent vectors)
// are the shortest form that reads back to the very same double: write, read, compare bits.
std::uint64_t bits(double v) {
  std::uint64_t b = 0;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

Eigen::MatrixXd awkward_values(Eigen::Index rows, Eigen::Index cols) {
  Eigen::MatrixXd m(rows, cols);
  const double fixed[] = {0.1,
                          1.0 / 3.0,
                          -0.0,
                          std::numeric_limits<double>::denorm_min(),
                          std::numeric_limits<double>::min(),
                          std::numeric_limits<double>::max(),
                          -std::numeric_limits<double>::max(),
                          std::numeric_limits<double>::epsilon(),
                          1e-300,
                          123456789012345678.0,
                          std::numeric_limits<double>::infinity(),
                          -std::numeric_limits<double>::infinity()};
  std::uint64_t state = 88172645463325252ull;  // xorshift64: any bit pattern that is a number
  for (Eigen::Index k = 0; k < m.size(); ++k) {
    if (k < Eigen::Index(std::size(fixed))) {
      m.data()[k] = fixed[k];
      continue;
    }
    double v = 0;
    do {
      state ^= state << 13;
      state ^= state >> 7;
      state ^= state << 17;
      std::memcpy(&v, &state, sizeof v);
    } while (!std::isfinite(v));
    m.data()[k] = v;
  }
  return m;
}

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("ifem_cli_args_test_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

TEST(TextOutput, RowsReadBackBitForBit) {
  const Eigen::MatrixXd m = awkward_values(500, 7);
  const std::string path = temp_path("rows.txt");
  write_rows(path, m);
  std::ifstream in(path);
  std::string line;
  Eigen::Index row = 0;
  while (std::getline(in, line)) {
    ASSERT_LT(row, m.rows());
    std::istringstream words(line);
    std::string word;
    Eigen::Index col = 0;
    while (words >> word) {
      ASSERT_LT(col, m.cols()) << line;
      double v = 0;
      const auto [ptr, ec] = std::from_chars(word.data(), word.data() + word.size(), v);
      ASSERT_TRUE(ec == std::errc() && ptr == word.data() + word.size()) << word;
      EXPECT_EQ(bits(v), bits(m(row, col))) << word << " at (" << row << ", " << col << ")";
      ++col;
    }
    EXPECT_EQ(col, m.cols());
    EXPECT_EQ(line.find("  "), std::string::npos) << "one space between columns";
    ++row;
  }
  EXPECT_EQ(row, m.rows());
  std::remove(path.c_str());
}

TEST(TextOutput, ValuesReadBackBitForBitInTheirShortestForm) {
  Eigen::MatrixXd m = awkward_values(20000, 1);  // several flushes of the writer's buffer
  m(20, 0) = std::nan("");
  const Eigen::VectorXd v = m.col(0);
  const std::string path = temp_path("values.txt");
  io::write_values(path, v);
  const Eigen::VectorXd back = io::read_values(path);
  ASSERT_EQ(back.size(), v.size());
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    if (std::isnan(v[i])) {
      EXPECT_TRUE(std::isnan(back[i])) << i;
    } else {
      EXPECT_EQ(bits(back[i]), bits(v[i])) << i;
    }
  }
  std::ifstream in(path);
  std::string first;
  std::getline(in, first);
  EXPECT_EQ(first, "0.1");  // the shortest form, not %.17g's 0.10000000000000001
  std::remove(path.c_str());
}

TEST(TextOutput, UnwritablePathIsAnIoError) {
  EXPECT_THROW(write_rows("/nonexistent-dir/x.txt", Eigen::MatrixXd::Ones(2, 2)), IoError);
}

}  // namespace
}  // namespace ifem::cli
