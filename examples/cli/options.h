// The `ifem` command line as data: each command declares its options in a table (OptionSpec).
// The table becomes a CLI11 application (libcli11-dev) that parses the command line and
// generates `--help`, so the two cannot drift apart; the table adds what CLI11 does not say the
// way ifem must: checked values (no partial parses, no silent narrowing, ranges), the messages
// of bad command lines (exit code 2) and limits known only after loading the input.
// The parser is unit-tested on its own (cli_args_test).
#pragma once

#include <limits>
#include <map>
#include <string>
#include <vector>

#include "intrinsic/core/errors.h"
#include "intrinsic/core/types.h"

namespace ifem::cli {

/// A command line the command cannot run with: unknown option, missing or malformed value,
/// value out of its range (also ranges known only after loading the input, such as a vertex
/// id ≥ #V). `ifem` exits with code 2 on it (1 on other ifem::Error).
class UsageError : public Error {
 public:
  using Error::Error;
};

/// What an option's value is; decides how it is parsed and how its range is described.
enum class Kind {
  kFlag,        ///< no value
  kCount,       ///< an integer (fits Index, int32)
  kVertex,      ///< one vertex id of the input: integer ≥ 0, < #V once the input is loaded
  kVertexList,  ///< comma-separated vertex ids ("3,17,42"), each as kVertex
  kReal,        ///< a finite double (no nan, no inf, no overflow)
  kText,        ///< a non-empty string (a path, a prefix)
};

/// A bound that depends on the input, checked by check_input_limits() right after loading.
enum class InputLimit {
  kNone,
  kBelowVertexCount,  ///< value (each id of a list) < #V of the input
  kBelowPointCount,   ///< value < #points, on the point-cloud path only (--knn)
};

/// One option of one command, as data. Build with the factories below and chain modifiers:
///   count("k", "K").short_alias('k').at_least(1).defaults_to("10").explain("...")
struct OptionSpec {
  std::string name;           ///< long name without "--" ("output")
  char alias = 0;             ///< short alias ('o' for -o), 0 for none
  Kind kind = Kind::kFlag;    ///< how the value is parsed
  std::string placeholder;    ///< the value's name in help ("OUT", "K")
  std::string default_value;  ///< parsed like a command-line value and shown in help; "" = none
  std::string help;           ///< help text; '\n' separates lines
  double lo = -std::numeric_limits<double>::infinity();  ///< lower bound of the value
  double hi = std::numeric_limits<double>::infinity();   ///< upper bound of the value
  bool lo_open = false, hi_open = false;                 ///< exclusive bounds
  bool required = false;                                 ///< the command fails without it
  InputLimit input_limit = InputLimit::kNone;
  std::vector<std::string> extensions;  ///< kText: allowed lowercased extensions (".ply"), or any

  OptionSpec& short_alias(char c);
  OptionSpec& at_least(double v);  ///< value ≥ v
  OptionSpec& above(double v);     ///< value > v
  OptionSpec& at_most(double v);   ///< value ≤ v
  OptionSpec& defaults_to(std::string v);
  OptionSpec& explain(std::string text);
  OptionSpec& mandatory();
  OptionSpec& limited_by(InputLimit limit);
  OptionSpec& with_extensions(std::vector<std::string> exts);

  /// "-k", "--output": how messages name the option (the short form when the long name is it).
  std::string display() const;
  /// "an integer in [1, 2147483647]", "a number in (0, 30]": the allowed values, for messages
  /// and help; "" for flags.
  std::string describe_range() const;
  /// The effective integer bounds of kCount / kVertex / kVertexList (within Index's range).
  long long int_lo() const;
  long long int_hi() const;
};

/// A number as help text, messages and progress lines show it (1e-05, 0.4, 25, ∞).
std::string format_number(double v);

OptionSpec flag(std::string name);
OptionSpec count(std::string name, std::string placeholder);  ///< integer, default range ≥ 0
OptionSpec vertex(std::string name, std::string placeholder);
OptionSpec vertex_list(std::string name, std::string placeholder);
OptionSpec real(std::string name, std::string placeholder);
OptionSpec text(std::string name, std::string placeholder);

/// Options under one heading of the help ("Options", "Surface options", ...). Shared groups
/// (surface, refinement) are appended to the commands that understand them.
struct OptionGroup {
  std::string title;
  std::vector<OptionSpec> options;
};

/// Everything the parser and the help need to know about one command.
struct CommandSpec {
  std::string name;                      ///< "distance"
  std::vector<std::string> positionals;  ///< placeholders of the required positional arguments
  std::string prose;                     ///< what the command does, between usage and options
  std::vector<OptionGroup> groups;       ///< the first one is the command's own ("Options")
  std::string epilogue;                  ///< examples etc., after the option list
};

/// The generated `ifem NAME --help` (CLI11's help of the table's application, in ifem's layout):
/// usage line (positionals, required options), the prose, every group's options with
/// placeholder, default and range, then the epilogue.
std::string render_help(const CommandSpec& spec);

/// Checked conversions of one value for `spec` (no partial parses, no silent narrowing).
/// @throws UsageError naming the option, the value and the allowed range
long long parse_integer(const OptionSpec& spec, const std::string& value);
double parse_real(const OptionSpec& spec, const std::string& value);
std::vector<Index> parse_vertex_list(const OptionSpec& spec, const std::string& value);

/// A parsed command line of one command: positionals and option values, each already checked
/// against its spec. Typed access falls back on the spec's default.
class Args {
 public:
  /// Parses argv[0..argc) (the words after the command name) with CLI11: "--name value",
  /// "--name=value", the short aliases ("-o value", "-ovalue"), "--" ends options. -h/--help is
  /// always accepted. Every value is checked against its spec here (parse_integer() etc.).
  /// @throws UsageError on unknown options, missing / malformed / out-of-range values, a value
  ///   given to a flag, an option given twice
  Args(const CommandSpec& spec, int argc, const char* const* argv);

  /// Checks what --help may skip: the number of positionals and the required options.
  /// @throws UsageError
  void check_complete() const;

  const std::vector<std::string>& positional() const { return positional_; }
  /// Whether the option (or flag) was given on the command line.
  bool has(const std::string& name) const { return values_.count(name) > 0; }
  /// The raw text as given (or the default); for kText options.
  std::string get(const std::string& name) const;
  /// kCount / kVertex: the value given, else the spec's default.
  Index count(const std::string& name) const;
  /// kCount / kVertex: the value given, else `fallback` (a default that depends on context).
  Index count_or(const std::string& name, Index fallback) const;
  /// kReal: the value given, else the spec's default.
  double real(const std::string& name) const;
  /// kReal: the value given, else `fallback`.
  double real_or(const std::string& name, double fallback) const;
  /// kVertexList: the ids given (empty when not given).
  std::vector<Index> vertices(const std::string& name) const;

  /// The spec of a declared option. @throws std::logic_error for an undeclared name (a bug)
  const OptionSpec& spec(const std::string& name) const;
  const std::vector<OptionSpec>& specs() const { return specs_; }

 private:
  const OptionSpec* find_long(const std::string& name) const;
  std::string text_or_default(const OptionSpec& spec) const;

  std::vector<OptionSpec> specs_;
  std::vector<std::string> positional_names_;
  std::vector<std::string> positional_;
  std::map<std::string, std::string> values_;
};

/// Checks every option with an InputLimit that was given (or has a default, except
/// kBelowPointCount: the point-cloud pipeline clamps its default) against the loaded input: #V
/// vertices (`n_vertices`), on the point-cloud path when `pointcloud`.
/// @throws UsageError naming the option, the value and the limit
void check_input_limits(const Args& args, Index n_vertices, bool pointcloud);

}  // namespace ifem::cli
