// The curves file (solvers::read_curves_file) and the checks of curves against an input
// (solvers::validate_curves): every form of the grammar, and every error naming its line (file)
// or its curve (validation). No mesh involved.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "intrinsic/core/errors.h"
#include "solvers/recipes/curves.h"

namespace ifem::solvers {
namespace {

using intrinsic::CurveShape;

// A file in the temp directory with `text`, removed at the end of the test; unique per test
// (ctest runs tests in parallel processes).
class CurvesFile : public ::testing::Test {
 protected:
  std::string write(const std::string& text) {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::filesystem::path p =
        std::filesystem::temp_directory_path() /
        ("ifem_curves_" + std::string(info->name()) + "_" + std::to_string(files_.size()) + ".txt");
    std::ofstream(p) << text;
    files_.push_back(p);
    return p.string();
  }
  void TearDown() override {
    for (const auto& p : files_) std::filesystem::remove(p);
  }
  // The IoError message of reading `text` ("" when it reads); `path` gets the file's path.
  std::string read_error(const std::string& text, std::string* path = nullptr) {
    const std::string p = write(text);
    if (path) *path = p;
    try {
      read_curves_file(p);
    } catch (const IoError& e) {
      return e.what();
    }
    return "";
  }
  // Reading a file whose line `line` is `bad` (after a good line, a comment and a blank line
  // when line == 4) fails with "path:line: " and `expected` in the message.
  void expect_line_error(const std::string& bad, const std::string& expected, int line = 4) {
    const std::string text = line == 4 ? "0 1 2\n# comment\n\n" + bad + "\n" : bad + "\n";
    std::string path;
    const std::string msg = read_error(text, &path);
    SCOPED_TRACE("line '" + bad + "': " + msg);
    EXPECT_EQ(msg.rfind(path + ":" + std::to_string(line) + ": ", 0), 0u);
    EXPECT_NE(msg.find(expected), std::string::npos);
  }

 private:
  std::vector<std::filesystem::path> files_;
};

TEST_F(CurvesFile, ParsesTheExamples) {
  const std::string path = write(
      "# the examples of solvers/recipes/curves.h and ifem poisson --help\n"
      "0.5 12 40 77                 # geodesic 12→40→77 held at 0.5\n"
      "closed 1 5 9 13              # closed loop through 5, 9, 13, held at 1\n"
      "bezier 0 3 8 20 31           # Bézier curve, control vertices 3 8 20 31, at 0\n"
      "0 0.5 1 : 12 40 77           # 0 at 12, 0.5 at 40, 1 at 77\n"
      "slit 0 1 12 40 77            # a cut: 0 on its left, 1 on its right\n"
      "\n"
      "slit 0 1 : 1 0 : 12 77       # a cut whose sides vary\n"
      "bezier=6 0 1 : 3 8 20 31     # Bézier, 6 rounds, 0 → 1\n");
  const std::vector<CurveCondition> c = read_curves_file(path);
  ASSERT_EQ(c.size(), 7u);
  using V = std::vector<Index>;
  using D = std::vector<double>;
  EXPECT_EQ(c[0].vertices, (V{12, 40, 77}));
  EXPECT_EQ(c[0].shape, CurveShape::kPath);
  EXPECT_EQ(c[0].values, D{0.5});
  EXPECT_FALSE(c[0].slit);
  EXPECT_TRUE(c[0].right_values.empty());
  EXPECT_EQ(c[0].origin, path + ":2");
  EXPECT_EQ(c[1].vertices, (V{5, 9, 13}));
  EXPECT_EQ(c[1].shape, CurveShape::kLoop);
  EXPECT_EQ(c[1].values, D{1});
  EXPECT_EQ(c[2].vertices, (V{3, 8, 20, 31}));
  EXPECT_EQ(c[2].shape, CurveShape::kBezier);
  EXPECT_EQ(c[2].bezier_rounds, 4);
  EXPECT_EQ(c[2].values, D{0});
  EXPECT_EQ(c[3].vertices, (V{12, 40, 77}));
  EXPECT_EQ(c[3].values, (D{0, 0.5, 1}));
  EXPECT_EQ(c[4].vertices, (V{12, 40, 77}));
  EXPECT_TRUE(c[4].slit);
  EXPECT_EQ(c[4].values, D{0});
  EXPECT_EQ(c[4].right_values, D{1});
  EXPECT_EQ(c[5].vertices, (V{12, 77}));
  EXPECT_TRUE(c[5].slit);
  EXPECT_EQ(c[5].values, (D{0, 1}));
  EXPECT_EQ(c[5].right_values, (D{1, 0}));
  EXPECT_EQ(c[5].origin, path + ":8");
  EXPECT_EQ(c[6].shape, CurveShape::kBezier);
  EXPECT_EQ(c[6].bezier_rounds, 6);
  EXPECT_EQ(c[6].vertices, (V{3, 8, 20, 31}));
  EXPECT_EQ(c[6].values, (D{0, 1}));
  EXPECT_EQ(c[6].origin, path + ":9");
  EXPECT_NO_THROW(validate_curves(c, 78, true));
}

TEST_F(CurvesFile, KeywordsInAnyOrderAndLaxSpacing) {
  const std::vector<CurveCondition> c =
      read_curves_file(write("slit closed -1.5 2e-3 4 5 6\r\n"
                             "\tbezier=0 slit 1 2 3 4\n"
                             "slit bezier=16 0 1: 1 0 :3 4\n"
                             "closed 0 1 2 3:5 6 7 8\n"
                             "   # only a comment\n"
                             "slit 7 : 9 : 0 1 2\n"
                             "bezier 0 1 : 3 4\n"));
  ASSERT_EQ(c.size(), 6u);
  EXPECT_EQ(c[0].shape, CurveShape::kLoop);
  EXPECT_TRUE(c[0].slit);
  EXPECT_EQ(c[0].values, std::vector<double>{-1.5});
  EXPECT_EQ(c[0].right_values, std::vector<double>{2e-3});
  EXPECT_EQ(c[0].vertices, (std::vector<Index>{4, 5, 6}));
  EXPECT_EQ(c[1].shape, CurveShape::kBezier);
  EXPECT_EQ(c[1].bezier_rounds, 0);
  EXPECT_TRUE(c[1].slit);
  EXPECT_EQ(c[1].vertices, (std::vector<Index>{3, 4}));
  EXPECT_EQ(c[2].bezier_rounds, 16);
  EXPECT_EQ(c[2].right_values, (std::vector<double>{1, 0}));
  EXPECT_EQ(c[3].shape, CurveShape::kLoop);
  EXPECT_EQ(c[3].values, (std::vector<double>{0, 1, 2, 3}));
  EXPECT_EQ(c[3].vertices, (std::vector<Index>{5, 6, 7, 8}));
  EXPECT_EQ(c[4].values, std::vector<double>{7});  // one value per side: constant
  EXPECT_EQ(c[4].right_values, std::vector<double>{9});
  EXPECT_EQ(c[4].origin.substr(c[4].origin.rfind(':')), ":6");
  EXPECT_EQ(c[5].values, (std::vector<double>{0, 1}));
  EXPECT_NO_THROW(validate_curves(c, 11, true));
}

TEST_F(CurvesFile, BadKeywords) {
  expect_line_error("clossed 1 2 3", "'clossed' is neither a keyword");
  expect_line_error("closed closed 1 2 3", "keyword 'closed' given twice");
  expect_line_error("slit slit 0 1 2 3", "keyword 'slit' given twice");
  expect_line_error("bezier bezier=3 0 1 2", "keyword 'bezier' given twice");
  expect_line_error("closed bezier 0 1 2", "'closed' and 'bezier' exclude each other");
  expect_line_error("bezier=2 closed 0 1 2", "'closed' and 'bezier' exclude each other");
  for (const char* r : {"bezier=17", "bezier=-1", "bezier=x", "bezier=", "bezier=2.5"}) {
    expect_line_error(std::string(r) + " 0 1 2", "'" + std::string(r) + "': expected bezier=R");
  }
  expect_line_error("closed", "expected a value and vertex ids after the keywords");
  expect_line_error("slit bezier", "expected LEFT RIGHT values and vertex ids");
  expect_line_error("0 closed 1 2", "(keywords come first on the line)");
}

TEST_F(CurvesFile, BadValuesAndVertices) {
  expect_line_error("nan 1 2", "'nan' is neither a keyword");
  expect_line_error("0 : inf 2 : 1 2", "separators");
  expect_line_error("0 1 : 1 2 : 3 4", "2 ':' separators, expected 1 (VALUES : VERTICES)");
  expect_line_error("0 inf : 1 2", "'inf' is not a value: expected a finite number");
  expect_line_error("0 1e400 : 1 2", "'1e400' is not a value");
  expect_line_error("slit 0 x 1 2", "'x' is not a RIGHT value");
  expect_line_error("slit 0 1 : x 2 : 1 2", "'x' is not a RIGHT value");
  for (const char* v : {"x", "-1", "1.5", "3x", "99999999999", "+3", "0x10"}) {
    expect_line_error(std::string("0 1 ") + v, "'" + std::string(v) + "' is not a vertex id");
  }
  expect_line_error("0 5", "a curve needs at least 2 vertex ids, got 1");
  expect_line_error("slit 0 1 2", "a curve needs at least 2 vertex ids, got 1");
  expect_line_error("slit 0", "expected LEFT RIGHT values, then vertex ids");
  expect_line_error("0 1 :", "at least 2 vertex ids, got 0");
  expect_line_error(": 1 2", "no values before ':'");
  expect_line_error("slit 0 : : 1 2", "no values before ':'");
  expect_line_error("slit 0 : 1 2", "1 ':' separators, expected 2 (LEFTS : RIGHTS : VERTICES)");
  expect_line_error("0 1 : 1 2 3", "2 values for 3 vertices: expected 1 (constant) or one per");
  expect_line_error("bezier 0 1 2 : 3 8 20 31", "3 values for 4 control points");
  expect_line_error("slit 0 1 : 1 : 2 3", "2 LEFT values but 1 RIGHT values");
}

TEST_F(CurvesFile, ErrorsNameTheirLine) {
  expect_line_error("0 1 x", "'x' is not a vertex id", 1);
  std::string path;
  const std::string msg = read_error("0 1 2\n\n\n# c\n1 2 3\n\n0 1 2 3 oops\n", &path);
  EXPECT_EQ(msg.rfind(path + ":7: 'oops' is not a vertex id", 0), 0u) << msg;
}

TEST_F(CurvesFile, EmptyMissingAndDirectory) {
  for (const char* text : {"", "\n\n", "# nothing\n   # here\n\t\n"}) {
    std::string path;
    const std::string msg = read_error(text, &path);
    EXPECT_EQ(msg, path + ": no curve in the file (every line is blank or a comment)");
  }
  const std::string missing =
      (std::filesystem::temp_directory_path() / "ifem_no_such_curves.txt").string();
  try {
    read_curves_file(missing);
    ADD_FAILURE() << "read a missing file";
  } catch (const IoError& e) {
    EXPECT_EQ(std::string(e.what()), missing + ": cannot open");
  }
  const std::string dir = std::filesystem::temp_directory_path().string();
  EXPECT_THROW(read_curves_file(dir), IoError);
}

// ---- validate_curves

CurveCondition curve(std::vector<Index> v, std::vector<double> values,
                     CurveShape shape = CurveShape::kPath, std::string origin = "c.txt:3") {
  CurveCondition c;
  c.vertices = std::move(v);
  c.values = std::move(values);
  c.shape = shape;
  c.origin = std::move(origin);
  return c;
}

// validate_curves({good, c}) throws InvalidInput starting with `name` and containing `what`.
void expect_invalid(const CurveCondition& c, const std::string& what, bool need_values = false,
                    const std::string& name = "c.txt:3") {
  const std::vector<CurveCondition> curves = {curve({0, 1}, {0}, CurveShape::kPath, ""), c};
  try {
    validate_curves(curves, 10, need_values);
    ADD_FAILURE() << "accepted; expected: " << what;
  } catch (const InvalidInput& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind(name + ": ", 0), 0u) << msg;
    EXPECT_NE(msg.find(what), std::string::npos) << msg;
  }
}

TEST(ValidateCurves, AcceptsEveryForm) {
  CurveCondition slit = curve({1, 2, 3}, {0, 1, 2});
  slit.slit = true;
  slit.right_values = {2, 1, 0};
  CurveCondition bare = curve({4, 5}, {});
  bare.slit = true;
  const std::vector<CurveCondition> ok = {curve({0, 9}, {1}),
                                          curve({0, 1, 0}, {}),  // open: may come back
                                          curve({0, 1}, {1, 2}, CurveShape::kLoop),
                                          curve({3, 4, 5}, {1, 2}, CurveShape::kBezier),
                                          curve({3, 4, 5}, {1}, CurveShape::kBezier),
                                          slit,
                                          bare};
  EXPECT_NO_THROW(validate_curves(ok, 10, false));
  EXPECT_NO_THROW(validate_curves({}, 10, true));
}

TEST(ValidateCurves, RefusesBadVertices) {
  expect_invalid(curve({0, 10}, {0}), "vertex 10 out of range [0, 10) (the input has 10");
  expect_invalid(curve({-1, 3}, {0}), "vertex -1 out of range [0, 10)");
  expect_invalid(curve({3}, {0}), "at least 2 vertices, got 1");
  expect_invalid(curve({}, {}), "at least 2 vertices, got 0");
  expect_invalid(curve({1, 2, 2, 3}, {0}), "vertex 2 twice in a row (positions 2 and 3)");
  expect_invalid(curve({1, 2, 1}, {0}, CurveShape::kLoop), "last vertex 1 is its first");
  expect_invalid(curve({1, 1}, {0}, CurveShape::kBezier), "vertex 1 twice in a row");
  // without an origin the curve is named by its index
  expect_invalid(curve({0, 12}, {0}, CurveShape::kPath, ""), "vertex 12 out of range", false,
                 "curve #1");
}

TEST(ValidateCurves, RefusesBadValues) {
  constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  expect_invalid(curve({1, 2, 3}, {0, 1}), "2 values for a path of 3 vertices");
  expect_invalid(curve({1, 2, 3}, {0, 1, 2, 3}, CurveShape::kLoop),
                 "4 values for a closed curve of 3 vertices: expected 1 (constant) or 3");
  expect_invalid(curve({1, 2, 3}, {0, 1, 2}, CurveShape::kBezier),
                 "3 values for a Bézier curve of 3 vertices: expected 1 (constant) or 2");
  expect_invalid(curve({1, 2}, {kNan}), "value 1 is not a finite number");
  expect_invalid(curve({1, 2}, {0, kInf}), "value 2 is not a finite number");
  CurveCondition slit = curve({1, 2}, {0, 1});
  slit.slit = true;
  slit.right_values = {1};
  expect_invalid(slit, "a slit with 2 left values and 1 right values");
  slit.right_values = {1, -kInf};
  expect_invalid(slit, "right value 2 is not a finite number");
  CurveCondition not_slit = curve({1, 2}, {0});
  not_slit.right_values = {1};
  expect_invalid(not_slit, "right values on a curve that is not a slit");
  CurveCondition rounds = curve({1, 2, 3}, {0}, CurveShape::kBezier);
  for (const int r : {-1, 17}) {
    rounds.bezier_rounds = r;
    expect_invalid(rounds, "Bézier rounds " + std::to_string(r) + " out of range [0, 16]");
  }
  expect_invalid(curve({1, 2}, {}), "carries no value", true);
  EXPECT_NO_THROW(validate_curves({curve({1, 2}, {})}, 10, false));
}

}  // namespace
}  // namespace ifem::solvers
