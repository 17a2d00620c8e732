// The shared command line (cli.hpp): the project's own reading of argv before the parser's.
#include "apps/cli.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <thread>

#include "sim/io/provenance.hpp"
#include "sim/io/scene.hpp"  // lg::InputError
#include "sim/io/toml_reader.hpp"  // lg::fmt

namespace lg::cli {
namespace {

const char* kWhere = "command line";

[[noreturn]] void usage(const std::string& key, const std::string& rule) { throw InputError(kWhere, 0, key, rule); }

std::string trimmed(const std::string& s) {
  const auto a = s.find_first_not_of(" \t"), b = s.find_last_not_of(" \t");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

// A value as an error quotes it: at most 60 characters.
std::string shownValue(const std::string& s) { return "'" + (s.size() > 60 ? s.substr(0, 57) + "..." : s) + "'"; }

// An argument that reads as an option, not as a value: "--x", or "-x" unless it starts a number.
bool looksLikeOption(const std::string& a) {
  if (a.size() < 2 || a[0] != '-') return false;
  if (a[1] == '-') return true;
  return !(std::isdigit(static_cast<unsigned char>(a[1])) || a[1] == '.');
}

const CLI::Option* findLong(const CLI::App& app, const std::string& name) {
  for (const CLI::Option* o : app.get_options())
    if (o->check_lname(name)) return o;
  return nullptr;
}
bool isSwitch(const CLI::Option* o) { return o->get_expected_max() == 0; }
bool isRepeatable(const CLI::Option* o) { return o->get_items_expected_max() > 1; }

// The closest option name (for "did you mean"), if any is within two edits.
std::string nearest(const CLI::App& app, const std::string& name) {
  auto distance = [](const std::string& a, const std::string& b) {
    std::vector<size_t> d(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) d[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
      size_t prev = d[0];
      d[0] = i;
      for (size_t j = 1; j <= b.size(); ++j) {
        const size_t t = d[j];
        d[j] = std::min({d[j] + 1, d[j - 1] + 1, prev + (a[i - 1] == b[j - 1] ? 0 : 1)});
        prev = t;
      }
    }
    return d[b.size()];
  };
  std::string best;
  size_t bd = 3;
  for (const CLI::Option* o : app.get_options())
    for (const std::string& l : o->get_lnames())
      if (const size_t dd = distance(name.substr(0, 40), l); dd < bd) bd = dd, best = "--" + l;
  return best;
}

// "simulate SCENE [options]", "compare A B [options]".
std::string usageLine(const std::string& program, const std::vector<std::string>& positionals) {
  std::string line = program;
  for (std::string up : positionals) {
    for (char& c : up) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    line += " " + up;
  }
  return line + " [options]";
}

// The app's positional arguments (its input files), in the order declared.
std::vector<const CLI::Option*> positionalsOf(const CLI::App& app) {
  std::vector<const CLI::Option*> positionals;
  for (const CLI::Option* o : app.get_options())
    if (o->get_lnames().empty() && o->get_snames().empty() && !o->get_name(true).empty()) positionals.push_back(o);
  return positionals;
}

// The value of the option 'name' (o) at argv[i]: after '=', or the next argument (i moves on), never an
// option and never empty.
std::string optionValue(const CLI::Option* o, const std::string& name, const std::string& a, int& i, int argc, char** argv) {
  std::string value;
  if (const auto eq = a.find('='); eq != std::string::npos) {
    value = a.substr(eq + 1);
  } else {
    if (i + 1 >= argc) usage(name, "needs a value: " + name + " " + o->get_type_name() + " (see --help)");
    value = argv[i + 1];
    if (looksLikeOption(value))
      usage(name, "needs a value, not the option " + shownValue(value) + ": " + name + " " + o->get_type_name());
    ++i;
  }
  if (trimmed(value).empty()) usage(name, "the value is empty: " + name + " " + o->get_type_name() + " (see --help)");
  return value;
}

// The positional arguments checked: each input file once (where the app has them), appended after "--".
void appendPositional(const CLI::App& app, const std::string& program, const std::vector<std::string>& positionals,
                      std::vector<std::string>& out) {
  const std::vector<const CLI::Option*> declared = positionalsOf(app);
  if (declared.empty()) {
    if (!positionals.empty()) usage(positionals[0].substr(0, 40), program + " takes no file argument (see --help)");
    return;
  }
  std::vector<std::string> names;
  for (const CLI::Option* o : declared) names.push_back(o->get_name(true));
  if (positionals.empty() && !declared[0]->get_required()) return;
  static const char* kOrdinal[] = {"first", "second", "third"};
  if (positionals.size() < declared.size()) {
    const std::size_t k = positionals.size();
    usage(names[k], "missing: the " + names[k] + " file comes " + (k < 3 ? kOrdinal[k] : "next") + ": " +
                        usageLine(program, names) + " (see --help)");
  }
  if (positionals.size() > declared.size())
    usage(names.back(), (declared.size() == 1 ? "one " + names[0] + " file only: " : std::to_string(declared.size()) + " files only: ") +
                            shownValue(positionals[declared.size()]) + " is one too many (options are written --name VALUE)");
  for (std::size_t k = 0; k < positionals.size(); ++k)
    if (positionals[k].empty()) usage(names[k], "the file name is empty");
  out.push_back("--");
  for (const auto& p : positionals) out.push_back(p);
}

// argv read by the project's rules, rewritten for the parser as "--name=value" and switches, then "--"
// and the positional argument: no value can be taken for an option, nor an option for a value.
std::vector<std::string> normalised(const CLI::App& app, const std::string& program, int argc, char** argv) {
  std::vector<std::string> out{argv[0]}, positionals;
  std::map<std::string, std::string> given;  // single-valued options: their value
  bool rest = false;                         // after "--": positional arguments only
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (rest || !looksLikeOption(a)) {
      positionals.push_back(a);
      continue;
    }
    if (a == "--") {
      rest = true;
      continue;
    }
    if (a[1] != '-') usage(a.substr(0, 40), "not an option of " + program + " (options are written --name; see --help)");
    const std::string name = a.substr(0, a.find('='));
    const CLI::Option* o = findLong(app, name.substr(2));
    if (!o) {
      const std::string near = nearest(app, name.substr(2));
      usage(name.size() > 40 ? name.substr(0, 37) + "..." : name,
            "not an option of " + program + (near.empty() ? "" : " (did you mean " + near + "?)") + "; see --help");
    }
    if (isSwitch(o)) {
      if (a.find('=') != std::string::npos) usage(name, "a switch takes no value: write " + name + " alone");
      out.push_back(name);
      continue;
    }
    const std::string value = optionValue(o, name, a, i, argc, argv);
    if (!isRepeatable(o)) {
      if (const auto it = given.find(name); it != given.end())
        usage(name, "given twice (" + shownValue(it->second) + " and " + shownValue(value) + "): give it once");
      given[name] = value;
    }
    out.push_back(name + "=" + value);
  }
  appendPositional(app, program, positionals, out);
  return out;
}

CLI::Option* withRule(CLI::App& app, const std::string& name, const std::string& help, const std::string& type,
                      std::function<void(const std::string&)> read) {
  return app.add_option_function<std::string>(name, std::move(read), help)->type_name(type);
}

}  // namespace

std::string version(const std::string& program) { return versionLine(program); }

void addVersion(CLI::App& app, const std::string& program) {
  app.set_version_flag("--version", version(program), "print the version and exit");
}

std::string integerError(const std::string& text, long long lo, long long hi, const std::string& note, long long* value) {
  const std::string t = trimmed(text);
  const std::string range = "in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]" + (note.empty() ? "" : " (" + note + ")");
  const bool digits = !t.empty() && std::all_of(t.begin() + (t[0] == '-' || t[0] == '+'), t.end(),
                                                 [](char c) { return std::isdigit(static_cast<unsigned char>(c)); }) &&
                      t.size() > static_cast<size_t>(t[0] == '-' || t[0] == '+');
  long long v = 0;
  if (digits) {
    errno = 0;
    v = std::strtoll(t.c_str(), nullptr, 10);
    if (errno == ERANGE) return "value " + shownValue(t) + " must be an integer " + range;
  } else {
    double d = 0;
    char* end = nullptr;
    const bool hex = t.find_first_of("xX") != std::string::npos;
    if (!t.empty() && !hex) d = std::strtod(t.c_str(), &end);
    if (t.empty() || hex || end != t.c_str() + t.size() || !std::isfinite(d))
      return "value " + shownValue(text) + " is not an integer: it must be an integer " + range;
    if (d != std::floor(d) || std::abs(d) > 9.007199254740992e15)
      return "value " + shownValue(t) + " is not a whole number: it must be an integer " + range;
    v = static_cast<long long>(d);
  }
  if (v < lo || v > hi) return "value " + t + " must be an integer " + range;
  if (value) *value = v;
  return "";
}

std::string numberError(const std::string& text, bool positive, const std::string& unit, double* value) {
  const std::string t = trimmed(text);
  const std::string u = unit.empty() ? "" : " " + unit;
  double d = 0;
  char* end = nullptr;
  const bool hex = t.find_first_of("xX") != std::string::npos;
  if (!t.empty() && !hex) d = std::strtod(t.c_str(), &end);
  if (t.empty() || hex || end != t.c_str() + t.size())
    return "value " + shownValue(text) + " is not a number" + (unit.empty() ? "" : " of " + unit) + " (e.g. 1e-3)";
  if (!std::isfinite(d)) return "value " + shownValue(t) + " must be a finite number" + (positive ? " > 0" : "");
  if (positive && !(d > 0)) return "value " + t + u + " must be > 0";
  if (value) *value = d;
  return "";
}

CLI::Option* addInteger(CLI::App& app, const std::string& name, long long& target, const std::string& help, long long lo,
                        long long hi, const std::string& note) {
  return withRule(app, name, help, "INT", [&target, name, lo, hi, note](const std::string& s) {
    if (const std::string e = integerError(s, lo, hi, note, &target); !e.empty()) usage(name, e);
  });
}
CLI::Option* addInteger(CLI::App& app, const std::string& name, int& target, const std::string& help, long long lo,
                        long long hi, const std::string& note) {
  return withRule(app, name, help, "INT", [&target, name, lo, hi, note](const std::string& s) {
    long long v = 0;
    if (const std::string e = integerError(s, lo, hi, note, &v); !e.empty()) usage(name, e);
    target = static_cast<int>(v);
  });
}
CLI::Option* addNumber(CLI::App& app, const std::string& name, double& target, const std::string& help, bool positive,
                       const std::string& unit) {
  return withRule(app, name, help, "NUMBER", [&target, name, positive, unit](const std::string& s) {
    if (const std::string e = numberError(s, positive, unit, &target); !e.empty()) usage(name, e);
  });
}
CLI::Option* addChoice(CLI::App& app, const std::string& name, std::string& target, const std::string& help,
                       const std::vector<std::string>& choices) {
  return withRule(app, name, help, "NAME", [&target, name, choices](const std::string& s) {
    if (std::find(choices.begin(), choices.end(), s) == choices.end()) {
      std::string list;
      for (size_t i = 0; i < choices.size(); ++i)
        list += (i == 0 ? "" : i + 1 == choices.size() ? " or " : ", ") + choices[i];
      usage(name, "value " + shownValue(s) + " must be " + list);
    }
    target = s;
  });
}
CLI::Option* addText(CLI::App& app, const std::string& name, std::string& target, const std::string& help) {
  return withRule(app, name, help, "TEXT", [&target](const std::string& s) { target = s; });
}
CLI::Option* addTexts(CLI::App& app, const std::string& name, std::vector<std::string>& target, const std::string& help) {
  return app.add_option(name, target, help)->type_name("TEXT")->allow_extra_args(false);
}
CLI::Option* addInputFile(CLI::App& app, const std::string& name, std::string& target, const std::string& help) {
  return app.add_option(name, target, help)->required()->type_name("FILE");
}
CLI::Option* addThreads(CLI::App& app, int& threads, const std::string& over) {
  return addInteger(app, "--threads", threads, "threads over " + over + " (default 0: all cores)", 0, 4096, "0: all cores");
}
int resolveThreads(int threads) {
  return threads > 0 ? threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

int parse(CLI::App& app, int argc, char** argv, bool speak) {
  for (int i = 1; i < argc; ++i) {  // --help and --version answer whatever else is there
    const std::string a = argv[i];
    if (a == "--") break;
    if (a == "--help" || a == "-h" || a == "--version") {
      std::string only[2] = {argv[0], a == "-h" ? "--help" : a};
      char* args[2] = {only[0].data(), only[1].data()};
      try {
        app.parse(2, args);
      } catch (const CLI::ParseError& e) {
        return speak ? app.exit(e) : e.get_exit_code();
      }
      return kOk;
    }
  }
  try {
    const std::vector<std::string> args = normalised(app, std::filesystem::path(argv[0]).filename().string(), argc, argv);
    std::vector<char*> ptrs;
    for (const auto& s : args) ptrs.push_back(const_cast<char*>(s.c_str()));
    app.parse(static_cast<int>(ptrs.size()), ptrs.data());
    return -1;
  } catch (const InputError& e) {
    if (speak) std::fprintf(stderr, "error: %s\n", e.what());
    return kUsage;
  } catch (const CLI::ParseError& e) {  // not reached for what normalised() checks; the parser's words, marked
    if (speak) std::fprintf(stderr, "error: %s: %s (see --help)\n", kWhere, e.what());
    return kUsage;
  }
}

}  // namespace lg::cli
