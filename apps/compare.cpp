// compare A B [--case NAME]... [--out DIR] [--threads N] [--quiet]
// Two designs side by side: the scene values that differ (A -> B, in the order of B's file), then
// every drop case the two scenes share (or the named ones) run on each, with every metric of the
// catalogue (sim/drop/metrics.hpp) as A, B, B - A and the relative change. The usual pair is a scene and a study's optimum (data/seed_gear.toml
// and out/study/best.toml), or a scene and a variant of it. Writes DIR/compare.csv (one row per case and
// metric) and DIR/compare.json (with the provenance block and the differing values).
// Exit status: 0 done, 1 a case failed or an output could not be written, 2 bad input (nothing
// written), 130 interrupted (nothing written).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "apps/cli.hpp"
#include "sim/io/files.hpp"
#include "sim/core/format.hpp"
#include "sim/io/json.hpp"
#include "sim/io/provenance.hpp"
#include "sim/io/scene.hpp"
#include "sim/io/toml_rewrite.hpp"  // tomlFloat, sameToml
#include "sim/drop/metrics.hpp"
#include "sim/drop/run.hpp"

namespace {

struct Options {
  std::string a, b, outDir = "out/compare";
  std::vector<std::string> cases;
  int threads = 0;
  bool quiet = false;
};

// A value of a scene document as one short line.
std::string shown(const toml::node& n) {
  if (const auto* f = n.as_floating_point()) return lg::tomlFloat(f->get());
  if (const auto* i = n.as_integer()) return std::to_string(i->get());
  if (const auto* s = n.as_string()) return "\"" + s->get() + "\"";
  if (const auto* b = n.as_boolean()) return b->get() ? "true" : "false";
  std::ostringstream o;
  if (const auto* a = n.as_array()) o << *a;
  else if (const auto* t = n.as_table()) {
    toml::table copy = *t;
    copy.is_inline(true);
    o << copy;
  }
  std::string s = o.str();
  for (char& c : s) if (c == '\n') c = ' ';
  return s.size() > 60 ? s.substr(0, 57) + "..." : s;
}

struct Difference {
  std::string path, a, b;  // a or b "(absent)" where one scene lacks the key
  int line = 0;            // where the value stands in B's file (A's where B lacks it): the order shown
};

// The values of two scene documents that differ, by path: the elements of [[body]], [[joint]], [[stop]],
// [[force]] and [[case]] by their names ("strut.f1"), other tables by their keys ("solver.rtol").
void differences(const toml::node* a, const toml::node* b, const std::string& path, std::vector<Difference>& out) {
  if (a && b && lg::sameToml(*a, *b)) return;
  const auto* ta = a ? a->as_table() : nullptr;
  const auto* tb = b ? b->as_table() : nullptr;
  if (ta && tb) {
    for (const auto& [k, v] : *ta) differences(&v, tb->get(k.str()), path.empty() ? std::string(k.str()) : path + "." + std::string(k.str()), out);
    for (const auto& [k, v] : *tb)
      if (!ta->contains(k.str())) differences(nullptr, &v, path.empty() ? std::string(k.str()) : path + "." + std::string(k.str()), out);
    return;
  }
  const auto* xa = a ? a->as_array() : nullptr;
  const auto* xb = b ? b->as_array() : nullptr;
  auto named = [](const toml::array* x) {
    if (!x || !x->is_array_of_tables()) return false;
    for (const auto& e : *x)
      if (!e.as_table()->get_as<std::string>("name")) return false;
    return true;
  };
  if (xa && xb && named(xa) && named(xb)) {  // elements matched by name: "strut.f1", "limit.sink_speed"
    auto find = [](const toml::array& x, const std::string& name) -> const toml::node* {
      for (const auto& e : x)
        if (e.as_table()->get_as<std::string>("name")->get() == name) return &e;
      return nullptr;
    };
    for (const auto& e : *xa) {
      const std::string name = e.as_table()->get_as<std::string>("name")->get();
      differences(&e, find(*xb, name), name, out);
    }
    for (const auto& e : *xb) {
      const std::string name = e.as_table()->get_as<std::string>("name")->get();
      if (!find(*xa, name)) differences(nullptr, &e, name, out);
    }
    return;
  }
  out.push_back({path, a ? shown(*a) : "(absent)", b ? shown(*b) : "(absent)",
                 static_cast<int>((b ? b : a)->source().begin.line)});
}

struct Row {
  const lg::MetricInfo* metric;
  double a, b;
};

// The metrics of one case on both designs: every catalogue metric that either has.
std::vector<Row> rows(const lg::CaseMetrics& a, const lg::CaseMetrics& b) {
  std::vector<Row> out;
  for (const auto& m : lg::metricCatalogue()) {
    const double va = lg::metricValue(a, m.name), vb = lg::metricValue(b, m.name);
    if (std::isfinite(va) || std::isfinite(vb)) out.push_back({&m, va, vb});
  }
  return out;
}

double relative(const Row& r) { return r.a != 0 && std::isfinite(r.a) ? (r.b - r.a) / std::abs(r.a) : NAN; }

// The cases to run: the named ones (each in both scenes), else every case of A that B has too.
std::vector<std::string> caseNames(const Options& o, const lg::Scene& a, const lg::Scene& b) {
  auto has = [](const lg::Scene& s, const std::string& n) {
    for (const auto& c : s.cases)
      if (c.name == n) return true;
    return false;
  };
  auto names = [](const lg::Scene& s) {
    std::string l;
    for (const auto& c : s.cases) l += (l.empty() ? "" : ", ") + c.name;
    return l.empty() ? std::string("none") : l;
  };
  std::vector<std::string> out;
  for (const auto& n : o.cases) {
    for (const lg::Scene* s : {&a, &b})
      if (!has(*s, n))
        throw lg::InputError("command line", 0, "--case",
                             "value '" + n + "' is not a case of " + s->file + " (its cases: " + names(*s) + ")");
    out.push_back(n);
  }
  if (!o.cases.empty()) return out;
  for (const auto& c : a.cases)
    if (has(b, c.name)) out.push_back(c.name);
  if (out.empty())
    throw lg::InputError("command line", 0, "B", "the scenes share no drop case (" + a.file + ": " + names(a) + "; " +
                                                     b.file + ": " + names(b) + "): name one with --case");
  return out;
}

const lg::DropCase& caseOf(const lg::Scene& s, const std::string& name) {
  for (const auto& c : s.cases)
    if (c.name == name) return c;
  return s.cases.front();  // (never: caseNames checked it)
}

std::string csvText(const std::vector<std::string>& names, const std::vector<lg::CaseResult>& ra,
                    const std::vector<lg::CaseResult>& rb) {
  std::ostringstream o;
  o << "case,metric,unit,A,B,B_minus_A,relative[-]\n";
  for (std::size_t i = 0; i < names.size(); ++i)
    for (const Row& r : rows(ra[i].metrics, rb[i].metrics))
      o << lg::csvField(names[i]) << "," << r.metric->name << "," << lg::csvField(r.metric->unit) << ","
        << lg::exactNumber(r.a) << "," << lg::exactNumber(r.b) << "," << lg::exactNumber(r.b - r.a) << ","
        << lg::exactNumber(relative(r)) << "\n";
  return o.str();
}

std::string jsonText(const Options& o, const std::vector<Difference>& diffs, const std::vector<std::string>& names,
                     const std::vector<lg::CaseResult>& ra, const std::vector<lg::CaseResult>& rb) {
  std::ostringstream j;
  j << "{\n  \"a\": " << lg::jsonString(o.a) << ",\n  \"b\": " << lg::jsonString(o.b) << ",\n  \"scene_differences\": [";
  for (std::size_t k = 0; k < diffs.size(); ++k)
    j << (k ? "," : "") << "\n    {\"path\": " << lg::jsonString(diffs[k].path) << ", \"a\": " << lg::jsonString(diffs[k].a)
      << ", \"b\": " << lg::jsonString(diffs[k].b) << "}";
  j << (diffs.empty() ? "" : "\n  ") << "],\n  \"cases\": [";
  for (std::size_t i = 0; i < names.size(); ++i) {
    const auto &ma = ra[i].metrics, &mb = rb[i].metrics;
    j << (i ? "," : "") << "\n    {\"name\": " << lg::jsonString(names[i]) << ", \"a_ok\": " << lg::jsonBool(ma.ok)
      << ", \"b_ok\": " << lg::jsonBool(mb.ok) << ", \"metrics\": [";
    const auto rs = rows(ma, mb);
    for (std::size_t k = 0; k < rs.size(); ++k)
      j << (k ? "," : "") << "\n      {\"name\": \"" << rs[k].metric->name << "\", \"unit\": " << lg::jsonString(rs[k].metric->unit)
        << ", \"a\": " << lg::jsonNumber(rs[k].a) << ", \"b\": " << lg::jsonNumber(rs[k].b)
        << ", \"difference\": " << lg::jsonNumber(rs[k].b - rs[k].a) << ", \"relative\": " << lg::jsonNumber(relative(rs[k])) << "}";
    j << "\n    ]}";
  }
  j << "\n  ]\n}\n";
  return j.str();
}

void printComparison(const Options& o, const std::vector<Difference>& diffs, const std::vector<std::string>& names,
                     const std::vector<lg::CaseResult>& ra, const std::vector<lg::CaseResult>& rb) {
  std::printf("A: %s\nB: %s\n", o.a.c_str(), o.b.c_str());
  if (diffs.empty()) std::printf("scene values: the same\n");
  else std::printf("scene values that differ (A -> B):\n");
  for (const auto& d : diffs) std::printf("  %-28s %s -> %s\n", d.path.c_str(), d.a.c_str(), d.b.c_str());
  for (std::size_t i = 0; i < names.size(); ++i) {
    const auto &ma = ra[i].metrics, &mb = rb[i].metrics;
    std::printf("\ncase %s%s%s\n", names[i].c_str(), ma.ok ? "" : (" (A failed: " + ma.message + ")").c_str(),
                mb.ok ? "" : (" (B failed: " + mb.message + ")").c_str());
    std::printf("  %-28s %-6s %13s %13s %13s %9s\n", "metric", "unit", "A", "B", "B - A", "change");
    for (const Row& r : rows(ma, mb)) {
      const double rel = relative(r);
      const std::string change = std::isfinite(rel) ? lg::shortNumber(100 * rel, 3) + " %" : "-";
      std::printf("  %-28s %-6s %13s %13s %13s %9s\n", r.metric->name, r.metric->unit, lg::shortNumber(r.a).c_str(),
                  lg::shortNumber(r.b).c_str(), lg::shortNumber(r.b - r.a).c_str(), change.c_str());
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Compares two designs: the scene values that differ and every shared drop case's metrics side by side"};
  lg::cli::addVersion(app, "compare");
  Options o;
  lg::cli::addInputFile(app, "A", o.a, "the first scene (TOML), e.g. data/seed_gear.toml");
  lg::cli::addInputFile(app, "B", o.b, "the second scene (TOML), e.g. out/study/best.toml");
  lg::cli::addTexts(app, "--case", o.cases, "a drop case of both scenes (repeatable; default: every case they share)");
  lg::cli::addText(app, "--out", o.outDir, "output directory (default out/compare)");
  lg::cli::addThreads(app, o.threads, "the drop cases");
  app.add_flag("--quiet", o.quiet, "print nothing but errors");
  if (const int rc = lg::cli::parse(app, argc, argv); rc >= 0) return rc;

  lg::Scene a, b;
  std::vector<std::string> names;
  try {
    a = lg::loadScene(o.a);
    b = lg::loadScene(o.b);
    names = caseNames(o, a, b);
  } catch (const lg::InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return lg::cli::kUsage;
  }
  try {
    lg::prepareOutputDir(o.outDir);
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return lg::cli::kFailed;
  }
  const int threads = lg::cli::resolveThreads(o.threads);
  lg::cli::installInterruptHandler();
  std::vector<lg::InputFile> inputs = lg::sceneInputs(a);
  for (auto& f : inputs) f.role += " A";
  for (auto f : lg::sceneInputs(b)) inputs.push_back({f.role + " B", f.path, f.sha256});
  const lg::Provenance provenance = lg::makeProvenance("compare", argc, argv, inputs);

  std::vector<lg::DropCase> ca, cb;
  for (const auto& n : names) {
    ca.push_back(caseOf(a, n));
    cb.push_back(caseOf(b, n));
  }
  lg::CaseOptions opt;
  opt.stop = [] { return lg::cli::interrupted(); };
  const std::vector<lg::CaseResult> ra = lg::runCases(a, ca, threads, opt), rb = lg::runCases(b, cb, threads, opt);
  if (lg::cli::interrupted()) {
    std::cerr << "interrupted: nothing written\n";
    return lg::cli::kInterrupted;
  }
  // The values that differ, in the order of B's file: the documents parsed again from the files' text
  // (the scene's own copy of its document keeps no source positions).
  std::vector<Difference> diffs;
  {
    const toml::table da = toml::parse(std::string_view(a.text), std::string_view(a.file));
    const toml::table db = toml::parse(std::string_view(b.text), std::string_view(b.file));
    differences(&da, &db, "", diffs);
    std::stable_sort(diffs.begin(), diffs.end(), [](const Difference& x, const Difference& y) { return x.line < y.line; });
  }

  int failed = 0;
  for (std::size_t i = 0; i < names.size(); ++i)
    for (const auto* r : {&ra[i], &rb[i]})
      if (!r->metrics.ok) {
        ++failed;
        std::cerr << "case " << names[i] << " failed on " << (r == &ra[i] ? o.a : o.b) << ": " << r->metrics.message << "\n";
      }
  try {
    lg::writeFileAtomic(o.outDir + "/compare.csv", csvText(names, ra, rb));
    lg::writeFileAtomic(o.outDir + "/compare.json", lg::stampJson(jsonText(o, diffs, names, ra, rb), &provenance));
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return lg::cli::kFailed;
  }
  if (!o.quiet) {
    printComparison(o, diffs, names, ra, rb);
    std::printf("wrote %s/compare.csv and compare.json\n", o.outDir.c_str());
  }
  return failed ? lg::cli::kFailed : lg::cli::kOk;
}
