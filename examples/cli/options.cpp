#include "options.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <sstream>
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

// ---- Args

Args::Args(const CommandSpec& command, int argc, const char* const* argv)
    : positional_names_(command.positionals) {
  for (const OptionGroup& g : command.groups) {
    specs_.insert(specs_.end(), g.options.begin(), g.options.end());
  }
  if (!find_long("help")) specs_.push_back(flag("help").short_alias('h'));
  bool options_done = false;
  for (int i = 0; i < argc; ++i) {
    const std::string a = argv[i];
    const bool looks_like_option = a.size() > 1 && a[0] == '-';
    if (options_done || !looks_like_option) {
      positional_.push_back(a);
      continue;
    }
    if (a == "--") {
      options_done = true;
      continue;
    }
    std::string key = a, value;
    bool inline_value = false;
    const OptionSpec* s = nullptr;
    if (a.compare(0, 2, "--") == 0) {
      key = a.substr(2);
      const auto eq = key.find('=');
      if (eq != std::string::npos) {
        inline_value = true;
        value = key.substr(eq + 1);
        key.resize(eq);
      }
      s = find_long(key);
      key = "--" + key;
    } else if (a.size() == 2) {
      s = find_short(a[1]);
    }
    if (!s) throw UsageError("unknown option " + key + " (see --help)");
    if (s->kind == Kind::kFlag) {
      if (inline_value) {
        throw UsageError("option " + s->display() + " takes no value, got '" + value + "'");
      }
      set(*s, "");
      continue;
    }
    if (!inline_value) {
      // "-o --quiet": the next word is an option, not this one's value
      const bool next_is_option = i + 1 < argc &&
                                  std::string(argv[i + 1]).compare(0, 2, "--") == 0 &&
                                  std::string(argv[i + 1]).size() > 2;
      if (i + 1 >= argc || next_is_option) {
        throw UsageError("option " + s->display() + " needs a value (" + s->placeholder + ": " +
                         s->describe_range() + ")");
      }
      value = argv[++i];
    }
    set(*s, value);
  }
}

void Args::set(const OptionSpec& spec, const std::string& value) {
  if (values_.count(spec.name)) throw UsageError("option " + spec.display() + " given twice");
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
          std::find(spec.extensions.begin(), spec.extensions.end(), io::file_extension(value)) ==
              spec.extensions.end()) {
        throw UsageError(spec.display() + " '" + value + "': the output must end in " +
                         join(spec.extensions, " or "));
      }
      break;
  }
  values_[spec.name] = value;
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

const OptionSpec* Args::find_short(char alias) const {
  for (const OptionSpec& s : specs_) {
    if (s.alias == alias) return &s;
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

namespace {

std::string option_column(const OptionSpec& s) {
  std::string col = "  ";
  if (s.alias && s.display() != "--" + s.name) {
    col += s.display();  // "-k": the short form is the name
  } else if (s.alias) {
    col += std::string("-") + s.alias + ", --" + s.name;
  } else {
    col += "--" + s.name;
  }
  if (s.kind != Kind::kFlag) col += " " + s.placeholder;
  return col;
}

void append_option(std::ostringstream& out, const OptionSpec& s) {
  std::vector<std::string> lines;
  std::istringstream help(s.help);
  for (std::string line; std::getline(help, line);) lines.push_back(line);
  std::string facts;
  if (!s.default_value.empty()) facts = "default " + s.default_value;
  if (s.kind != Kind::kFlag && s.kind != Kind::kText) {
    facts += (facts.empty() ? "" : "; ") + s.describe_range();
  }
  if (s.kind == Kind::kText && !s.extensions.empty()) facts += s.describe_range();
  if (s.required) facts += (facts.empty() ? "" : "; ") + std::string("required");
  if (!facts.empty()) lines.push_back("(" + facts + ")");
  if (lines.empty()) lines.push_back("");
  std::string col = option_column(s);
  if (col.size() + 1 > kHelpColumn) {
    out << col << "\n";
    col.clear();
  }
  for (const std::string& line : lines) {
    out << col << std::string(kHelpColumn - col.size(), ' ') << line << "\n";
    col.clear();
  }
}

}  // namespace

std::string render_help(const CommandSpec& spec) {
  std::ostringstream out;
  out << "usage: ifem " << spec.name;
  for (const std::string& p : spec.positionals) out << " " << p;
  for (const OptionGroup& g : spec.groups) {
    for (const OptionSpec& s : g.options) {
      if (s.required) {
        out << " " << (s.alias ? std::string("-") + s.alias : "--" + s.name) << " "
            << s.placeholder;
      }
    }
  }
  out << " [options]\n\n" << spec.prose;
  if (!spec.prose.empty() && spec.prose.back() != '\n') out << "\n";
  bool help_listed = false;
  for (std::size_t i = 0; i < spec.groups.size(); ++i) {
    const OptionGroup& g = spec.groups[i];
    out << "\n" << g.title << ":\n";
    for (const OptionSpec& s : g.options) {
      help_listed = help_listed || s.name == "help";
      append_option(out, s);
    }
    if (i == 0 && !help_listed) {
      append_option(out, flag("help").short_alias('h').explain("this help"));
      help_listed = true;
    }
  }
  if (!spec.epilogue.empty()) out << "\n" << spec.epilogue;
  return out.str();
}

}  // namespace ifem::cli
