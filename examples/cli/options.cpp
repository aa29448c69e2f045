#include "options.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <utility>

#include "intrinsic/io/mesh_io.h"

namespace ifem::cli {
namespace {

constexpr long long kIndexMin = std::numeric_limits<Index>::min();
constexpr long long kIndexMax = std::numeric_limits<Index>::max();
constexpr std::size_t kHelpColumn = 25;  // where an option's help text starts

std::string join(const std::vector<std::string>& items, const std::string& last_sep) {
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (i > 0) out += i + 1 == items.size() ? last_sep : ", ";
    out += items[i];
  }
  return out;
}

[[noreturn]] void fail_value(const OptionSpec& spec, const std::string& value,
                             const std::string& problem) {
  throw UsageError(spec.display() + " '" + value + "': " + problem + "; expected " +
                   spec.describe_range());
}

// One integer token: digits with an optional sign, nothing else, within the spec's range.
long long parse_integer_token(const OptionSpec& spec, const std::string& token,
                              const std::string& whole) {
  if (token.empty()) fail_value(spec, whole, "empty value");
  const std::string item = token == whole ? "" : "'" + token + "' ";
  const char* first = token.data();
  const char* last = token.data() + token.size();
  if (*first == '+' && token.size() > 1 && std::isdigit(static_cast<unsigned char>(first[1]))) {
    ++first;
  }
  long long v = 0;
  const auto [ptr, ec] = std::from_chars(first, last, v);
  if (ec == std::errc::result_out_of_range) fail_value(spec, whole, item + "out of range");
  if (ec != std::errc() || ptr != last) fail_value(spec, whole, item + "not an integer");
  if (v < spec.int_lo() || v > spec.int_hi()) fail_value(spec, whole, item + "out of range");
  return v;
}

bool in_real_range(const OptionSpec& spec, double v) {
  const bool lo_ok = spec.lo_open ? v > spec.lo : v >= spec.lo;
  const bool hi_ok = spec.hi_open ? v < spec.hi : v <= spec.hi;
  return lo_ok && hi_ok;
}

}  // namespace

// ---- OptionSpec

OptionSpec& OptionSpec::short_alias(char c) {
  alias = c;
  return *this;
}
OptionSpec& OptionSpec::at_least(double v) {
  lo = v;
  lo_open = false;
  return *this;
}
OptionSpec& OptionSpec::above(double v) {
  lo = v;
  lo_open = true;
  return *this;
}
OptionSpec& OptionSpec::at_most(double v) {
  hi = v;
  hi_open = false;
  return *this;
}
OptionSpec& OptionSpec::defaults_to(std::string v) {
  default_value = std::move(v);
  return *this;
}
OptionSpec& OptionSpec::explain(std::string t) {
  help = std::move(t);
  return *this;
}
OptionSpec& OptionSpec::mandatory() {
  required = true;
  return *this;
}
OptionSpec& OptionSpec::limited_by(InputLimit limit) {
  input_limit = limit;
  return *this;
}
OptionSpec& OptionSpec::with_extensions(std::vector<std::string> exts) {
  extensions = std::move(exts);
  return *this;
}

std::string OptionSpec::display() const {
  if (name.size() == 1 && alias == name[0]) return std::string("-") + alias;
  return "--" + name;
}

long long OptionSpec::int_lo() const {
  const double b = lo_open ? std::floor(lo) + 1 : std::ceil(lo);
  return static_cast<long long>(std::clamp(b, double(kIndexMin), double(kIndexMax)));
}

long long OptionSpec::int_hi() const {
  const double b = hi_open ? std::ceil(hi) - 1 : std::floor(hi);
  return static_cast<long long>(std::clamp(b, double(kIndexMin), double(kIndexMax)));
}

std::string OptionSpec::describe_range() const {
  switch (kind) {
    case Kind::kFlag:
      return "";
    case Kind::kCount:
    case Kind::kVertex:
    case Kind::kVertexList: {
      const std::string noun = kind == Kind::kCount    ? "an integer"
                               : kind == Kind::kVertex ? "a vertex id"
                                                       : "comma-separated vertex ids";
      return noun + " in [" + std::to_string(int_lo()) + ", " + std::to_string(int_hi()) + "]";
    }
    case Kind::kReal:
      return "a finite number in " + std::string(lo_open || std::isinf(lo) ? "(" : "[") +
             format_number(lo) + ", " + format_number(hi) + (hi_open || std::isinf(hi) ? ")" : "]");
    case Kind::kText:
      return extensions.empty() ? "a non-empty value"
                                : "a path ending in " + join(extensions, " or ");
  }
  return "";
}

std::string format_number(double v) {
  if (std::isinf(v)) return v > 0 ? "∞" : "-∞";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

OptionSpec flag(std::string name) {
  OptionSpec s;
  s.name = std::move(name);
  s.kind = Kind::kFlag;
  return s;
}

namespace {
OptionSpec valued(std::string name, Kind kind, std::string placeholder) {
  OptionSpec s;
  s.name = std::move(name);
  s.kind = kind;
  s.placeholder = std::move(placeholder);
  return s;
}
}  // namespace

OptionSpec count(std::string name, std::string placeholder) {
  return valued(std::move(name), Kind::kCount, std::move(placeholder)).at_least(0);
}
OptionSpec vertex(std::string name, std::string placeholder) {
  return valued(std::move(name), Kind::kVertex, std::move(placeholder))
      .at_least(0)
      .limited_by(InputLimit::kBelowVertexCount);
}
OptionSpec vertex_list(std::string name, std::string placeholder) {
  return valued(std::move(name), Kind::kVertexList, std::move(placeholder))
      .at_least(0)
      .limited_by(InputLimit::kBelowVertexCount);
}
OptionSpec real(std::string name, std::string placeholder) {
  return valued(std::move(name), Kind::kReal, std::move(placeholder));
}
OptionSpec text(std::string name, std::string placeholder) {
  return valued(std::move(name), Kind::kText, std::move(placeholder));
}

// ---- checked conversions

long long parse_integer(const OptionSpec& spec, const std::string& value) {
  return parse_integer_token(spec, value, value);
}

double parse_real(const OptionSpec& spec, const std::string& value) {
  if (value.empty()) fail_value(spec, value, "empty value");
  const char* first = value.data();
  const char* last = value.data() + value.size();
  if (*first == '+' && value.size() > 1) ++first;
  double v = 0;
  const auto [ptr, ec] = std::from_chars(first, last, v, std::chars_format::general);
  if (ec == std::errc::result_out_of_range) fail_value(spec, value, "out of the range of a double");
  if (ec != std::errc() || ptr != last) fail_value(spec, value, "not a number");
  if (!std::isfinite(v)) fail_value(spec, value, "not a finite number");
  if (!in_real_range(spec, v)) fail_value(spec, value, "out of range");
  return v;
}

std::vector<Index> parse_vertex_list(const OptionSpec& spec, const std::string& value) {
  if (value.empty()) fail_value(spec, value, "empty value");
  std::vector<Index> out;
  std::size_t begin = 0;
  while (true) {
    const std::size_t comma = value.find(',', begin);
    const std::string item = value.substr(begin, comma - begin);
    if (item.empty()) fail_value(spec, value, "empty id in the list");
    out.push_back(static_cast<Index>(parse_integer_token(spec, item, value)));
    if (comma == std::string::npos) break;
    begin = comma + 1;
  }
  return out;
}

// ---- the CLI11 application of one command

namespace {

// A value check that throws the table's own UsageError: CLI11 would otherwise prefix its
// ValidationError's text with the option's name ("--angle: ..."), and the messages are a contract.
// `help_range` is what the help shows as the allowed values ("" for none).
CLI::Validator value_check(const OptionSpec& spec, std::string help_range) {
  return CLI::Validator(
      [spec](std::string& value) -> std::string {
        // CLI11 hands an option the next word whatever it is: "-o --quiet" gives -o "--quiet"
        if (value.size() > 2 && value.compare(0, 2, "--") == 0) {
          throw UsageError("option " + spec.display() + " needs a value (" + spec.placeholder +
                           ": " + spec.describe_range() + ")");
        }
        switch (spec.kind) {
          case Kind::kFlag:
            break;
          case Kind::kCount:
          case Kind::kVertex:
            parse_integer(spec, value);
            break;
          case Kind::kVertexList:
            parse_vertex_list(spec, value);
            break;
          case Kind::kReal:
            parse_real(spec, value);
            break;
          case Kind::kText:
            if (value.empty()) fail_value(spec, value, "empty value");
            if (!spec.extensions.empty() &&
                std::find(spec.extensions.begin(), spec.extensions.end(),
                          io::file_extension(value)) == spec.extensions.end()) {
              throw UsageError(spec.display() + " '" + value + "': the output must end in " +
                               join(spec.extensions, " or "));
            }
            break;
        }
        return {};
      },
      std::move(help_range), "range");
}

// "-k", "-o,--output", "--mollify": CLI11's name list for a spec.
std::string cli11_names(const OptionSpec& s) {
  std::string names;
  if (s.alias) names = std::string("-") + s.alias + ",";
  return names + "--" + s.name;
}

// The generated help in ifem's layout: "usage: ifem NAME ARGS -o OUT [options]", the prose,
// every group as "Title:" with CLI11's option rows (help text from column kHelpColumn, then a
// line "(default ...; range; required)"), then the epilogue.
class HelpFormatter : public CLI::Formatter {
 public:
  HelpFormatter() { column_width(kHelpColumn); }

  std::string make_help(const CLI::App* app, std::string, CLI::AppFormatMode) const override {
    std::string out = make_usage(app, app->get_name()) + "\n" + make_description(app);
    for (const std::string& group : app->get_groups()) {  // no blank line between groups
      const auto opts = app->get_options(
          [&](const CLI::Option* o) { return o->get_group() == group && o->nonpositional(); });
      if (!group.empty() && !opts.empty()) out += make_group(group, false, opts);
    }
    return app->get_footer().empty() ? out : out + "\n" + app->get_footer();
  }

  std::string make_usage(const CLI::App* app, std::string name) const override {
    std::string out = "usage: ifem " + name;
    for (const CLI::Option* o : app->get_options()) {
      if (o->get_positional() && !o->get_option_text().empty()) out += " " + o->get_option_text();
    }
    for (const CLI::Option* o : app->get_options()) {
      if (o->nonpositional() && o->get_required()) {
        const auto& s = o->get_snames();
        out += " " + (s.empty() ? "--" + o->get_lnames().front() : "-" + s.front()) + " " +
               o->get_option_text();
      }
    }
    return out + " [options]\n";
  }

  std::string make_description(const CLI::App* app) const override {
    const std::string prose = app->get_description();
    return prose.empty() || prose.back() == '\n' ? prose : prose + "\n";
  }

  // "-k" (the short form is the name), "-o, --output", "--mollify"
  std::string make_option_name(const CLI::Option* o, bool) const override {
    const auto& shorts = o->get_snames();
    const std::string& name = o->get_lnames().front();
    if (shorts.empty()) return "--" + name;
    return shorts.front() == name ? "-" + name : "-" + shorts.front() + ", --" + name;
  }

  std::string make_option_opts(const CLI::Option* o) const override {
    return o->get_expected_max() == 0 ? "" : " " + o->get_option_text();  // " K"; flags: none
  }

  // the help text, then "(default 10; an integer in [1, 2147483647]; required)"
  std::string make_option_desc(const CLI::Option* o) const override {
    std::string desc = o->get_description();
    while (!desc.empty() && desc.back() == '\n') desc.pop_back();
    std::vector<std::string> facts;
    if (!o->get_default_str().empty()) facts.push_back("default " + o->get_default_str());
    // the range check's description: CLI11 appends it to the (empty) type name as ":RANGE"
    const std::string range = o->get_expected_max() == 0 ? "" : o->get_type_name();
    if (range.size() > 1) facts.push_back(range.substr(1));
    if (o->get_required()) facts.emplace_back("required");
    if (facts.empty()) return desc;
    return (desc.empty() ? "(" : desc + "\n(") + CLI::detail::join(facts, "; ") + ")";
  }
};

// The command's CLI11 application: every option of the table with its names, placeholder,
// default, range check and group; -h/--help after the first group's options; the words that are
// not options collected into `positional` (their number is check_complete()'s business).
// Unknown options are left to the caller (allow_extras): the message is ifem's, not CLI11's.
std::unique_ptr<CLI::App> make_app(const CommandSpec& command,
                                   std::vector<std::string>* positional) {
  auto app = std::make_unique<CLI::App>(command.prose, command.name);
  app->formatter(std::make_shared<HelpFormatter>());
  app->set_help_flag();  // -h/--help is an ordinary flag: run_command() prints the help
  app->allow_extras();
  app->footer(command.epilogue);
  std::string names;
  for (const std::string& p : command.positionals) names += (names.empty() ? "" : " ") + p;
  app->add_option("ARGS", *positional)->option_text(names)->group("");  // on the usage line only
  bool help_declared = false;
  for (const OptionGroup& g : command.groups) {
    for (const OptionSpec& s : g.options) help_declared = help_declared || s.name == "help";
  }
  for (std::size_t i = 0; i < command.groups.size(); ++i) {
    const OptionGroup& g = command.groups[i];
    for (const OptionSpec& s : g.options) {
      CLI::Option* o = nullptr;
      if (s.kind == Kind::kFlag) {
        o = app->add_flag(cli11_names(s), s.help);
      } else {
        const bool range_in_help = s.kind != Kind::kText || !s.extensions.empty();
        o = app->add_option(cli11_names(s), s.help)
                ->option_text(s.placeholder)
                ->type_name("")
                ->default_str(s.default_value)
                ->required(s.required)
                ->check(value_check(s, range_in_help ? s.describe_range() : ""));
      }
      o->group(g.title)->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
    }
    if (i == 0 && !help_declared) {
      app->add_flag("-h,--help", "this help")
          ->group(g.title)
          ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
    }
  }
  return app;
}

}  // namespace

// ---- Args

Args::Args(const CommandSpec& command, int argc, const char* const* argv)
    : positional_names_(command.positionals) {
  for (const OptionGroup& g : command.groups) {
    specs_.insert(specs_.end(), g.options.begin(), g.options.end());
  }
  if (!find_long("help")) specs_.push_back(flag("help").short_alias('h'));
  const std::unique_ptr<CLI::App> app = make_app(command, &positional_);

  // CLI11 reads "--name=" as "--name" and takes the next word; the table calls it an empty
  // value, so it is passed on as one. CLI11 wants the words in reverse order.
  std::vector<std::string> words;
  for (int i = 0; i < argc; ++i) {
    std::string w = argv[i];
    if (w == "--") {
      words.insert(words.end(), argv + i, argv + argc);
      break;
    }
    const OptionSpec* s = nullptr;
    if (w.size() > 3 && w.compare(0, 2, "--") == 0 && w.back() == '=') {
      s = find_long(w.substr(2, w.size() - 3));
    }
    if (s && s->kind != Kind::kFlag) {
      w.pop_back();
      words.push_back(w);
      words.emplace_back();
    } else {
      words.push_back(std::move(w));
    }
  }
  std::reverse(words.begin(), words.end());
  try {
    app->parse(words);
  } catch (const CLI::RequiredError&) {
    // a missing required option waits for check_complete(): --help needs none
  } catch (const CLI::ArgumentMismatch& e) {
    // the words ran out before an option's value ("... -k"): CLI11 names it first ("--k: ...")
    const std::string what = e.what();
    for (const OptionSpec& s : specs_) {
      if (what.rfind("--" + s.name + ":", 0) == 0) {
        throw UsageError("option " + s.display() + " needs a value (" + s.placeholder + ": " +
                         s.describe_range() + ")");
      }
    }
    throw UsageError(what);
  } catch (const CLI::ParseError& e) {
    throw UsageError(e.what());
  }
  for (const std::string& word : app->remaining()) {
    if (word == "--") continue;  // CLI11 keeps the end-of-options mark for a passthrough
    throw UsageError("unknown option " + word.substr(0, word.find('=')) + " (see --help)");
  }
  for (const OptionSpec& s : specs_) {
    const CLI::Option* o = app->get_option("--" + s.name);
    const std::vector<std::string>& given = o->results();
    if (given.empty()) continue;
    if (given.size() > 1) throw UsageError("option " + s.display() + " given twice");
    if (s.kind == Kind::kFlag) {
      // a bare flag's result is CLI11's "true"; "--flag=VALUE" leaves VALUE
      if (given[0] != "true") {
        throw UsageError("option " + s.display() + " takes no value, got '" + given[0] + "'");
      }
      values_[s.name] = "";
    } else {
      values_[s.name] = given[0];
    }
  }
}

void Args::check_complete() const {
  if (positional_.size() != positional_names_.size()) {
    std::string want = positional_names_.empty() ? "no arguments" : join(positional_names_, " ");
    if (positional_names_.size() == 1) want = "one input file " + want;
    throw UsageError("expected " + want + ", got " + std::to_string(positional_.size()) +
                     " (see --help)");
  }
  for (const OptionSpec& s : specs_) {
    if (s.required && !has(s.name)) {
      const std::string form = s.alias ? std::string("-") + s.alias : "--" + s.name;
      throw UsageError("missing " + form + " " + s.placeholder + " (see --help)");
    }
  }
}

const OptionSpec* Args::find_long(const std::string& name) const {
  for (const OptionSpec& s : specs_) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

const OptionSpec& Args::spec(const std::string& name) const {
  const OptionSpec* s = find_long(name);
  if (!s) throw std::logic_error("ifem: option --" + name + " is not in the command's table");
  return *s;
}

std::string Args::text_or_default(const OptionSpec& spec) const {
  const auto it = values_.find(spec.name);
  if (it != values_.end()) return it->second;
  if (spec.default_value.empty()) {
    throw std::logic_error("ifem: option --" + spec.name + " has no default");
  }
  return spec.default_value;
}

std::string Args::get(const std::string& name) const {
  const auto it = values_.find(name);
  return it != values_.end() ? it->second : spec(name).default_value;
}

Index Args::count(const std::string& name) const {
  const OptionSpec& s = spec(name);
  return static_cast<Index>(parse_integer(s, text_or_default(s)));
}

Index Args::count_or(const std::string& name, Index fallback) const {
  return has(name) ? count(name) : fallback;
}

double Args::real(const std::string& name) const {
  const OptionSpec& s = spec(name);
  return parse_real(s, text_or_default(s));
}

double Args::real_or(const std::string& name, double fallback) const {
  return has(name) ? real(name) : fallback;
}

std::vector<Index> Args::vertices(const std::string& name) const {
  const OptionSpec& s = spec(name);
  return has(name) ? parse_vertex_list(s, values_.at(name)) : std::vector<Index>{};
}

// ---- limits known after loading

void check_input_limits(const Args& args, Index n_vertices, bool pointcloud) {
  for (const OptionSpec& s : args.specs()) {
    if (s.input_limit == InputLimit::kNone) continue;
    // a default counts too (-k 10 on a 5-vertex mesh), except --knn's: the library clamps it
    const bool use_default =
        !s.default_value.empty() && s.input_limit != InputLimit::kBelowPointCount;
    if (!args.has(s.name) && !use_default) continue;
    if (s.input_limit == InputLimit::kBelowPointCount && !pointcloud) continue;
    const std::string what =
        s.input_limit == InputLimit::kBelowPointCount ? " points" : " vertices";
    const std::vector<Index> values = s.kind == Kind::kVertexList
                                          ? args.vertices(s.name)
                                          : std::vector<Index>{args.count(s.name)};
    for (const Index v : values) {
      if (v >= n_vertices) {
        throw UsageError(s.display() + " " + std::to_string(v) + ": " +
                         (s.kind == Kind::kCount ? "" : "vertex ") + "out of range [" +
                         std::to_string(s.int_lo()) + ", " + std::to_string(n_vertices) +
                         ") (the input has " + std::to_string(n_vertices) + what + ")");
      }
    }
  }
}

// ---- help

std::string render_help(const CommandSpec& spec) {
  std::vector<std::string> positional;
  return make_app(spec, &positional)->help();
}

}  // namespace ifem::cli
