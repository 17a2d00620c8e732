// certify SCENE [--basis NAME] [--nominal] [--out DIR] [--plots] [--threads N] [--quiet]
// Runs the certification drop-test matrix of a scene's [certification] table (sim/drop/certification.hpp)
// and the scene's own cases as checks, at every point of the scene's [envelope] where it declares one
// (sim/scene/envelope.hpp; --nominal: the nominal point only); writes DIR/compliance.json, DIR/compliance.md and, with
// --plots, one picture per case with its limits drawn. Exit status: 0 every matrix case passes,
// 1 a case fails (or an output could not be written), 2 bad input (nothing written), 130 interrupted.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "apps/cli.hpp"
#include "sim/io/certification.hpp"
#include "sim/io/compliance.hpp"
#include "sim/io/files.hpp"
#include "sim/io/plots.hpp"
#include "sim/io/provenance.hpp"
#include "sim/io/toml_reader.hpp"

namespace {

namespace fs = std::filesystem;

// The scene's certification matrix: its [certification] table, with 'basis' (if given) in place of the
// table's own; throws lg::InputError where the scene has none.
std::shared_ptr<const lg::Certification> matrixOf(const lg::Scene& scene, const std::string& scenePath,
                                                  const std::string& basis) {
  const toml::table* t = scene.doc["certification"].as_table();
  if (!t)
    throw lg::InputError(scenePath, 0, "certification",
                         "the scene has no [certification] table: add one with basis, landing_mass, limit_load_factor, "
                         "... (docs/certification.md)");
  return basis.empty() ? scene.certification
                       : std::make_shared<const lg::Certification>(lg::parseCertification(*t, scenePath, scene, basis));
}

// One picture per case (the matrix's, then the checks') with its limits, in DIR/plots; returns the
// report's pictures section. Throws where a file cannot be written.
std::string drawPictures(const lg::Scene& scene, const lg::Certification& spec, const lg::Compliance& c,
                         const std::vector<lg::CaseResult>& runs, const std::string& outDir) {
  std::string pictures;
  const fs::path pd = fs::path(outDir) / "plots";
  lg::prepareOutputDir(pd.string());
  const bool gp = lg::haveGnuplot();
  if (!gp) pictures = "gnuplot was not found: the data and scripts are in `plots/` (run `gnuplot <case>.gp` there).\n";
  if (c.servicing && c.servicing->ok) {
    std::string why;
    if (lg::drawServicingChart(*c.servicing, pd.string(), "servicing_chart", gp, &why)) pictures += "![servicing chart](plots/servicing_chart.png)\n\n";
    else if (gp) pictures += "Servicing chart missing: " + why + "\n\n";
  }
  std::vector<const lg::CaseVerdict*> all;
  for (const auto& v : c.cases) all.push_back(&v);
  for (const auto& v : c.checks) all.push_back(&v);
  for (size_t i = 0; i < all.size(); ++i) {
    const lg::CaseVerdict& v = *all[i];
    lg::CaseFigure f;
    char title[256];
    std::snprintf(title, sizeof title, "%s: %s (%s), V = %.3f m/s, L = %.3g, W = %.0f kg: %s", scene.name.c_str(),
                  v.name.c_str(), v.role == "check" ? "check" : lg::certKindName(v.cert.kind), v.cert.sinkSpeed,
                  v.cert.liftRatio, v.cert.mass, v.pass ? "PASS" : "FAIL");
    f.title = title;
    f.run = &runs[i];
    f.limits = lg::compliancePlotLimits(scene, spec, v);
    f.drawElementsOf(scene);
    const std::string stem = lg::safeFileStem(v.name);
    std::string why;
    if (lg::drawCaseFigure(f, pd.string(), stem, gp, &why)) {
      if (gp) pictures += "![" + v.name + "](plots/" + stem + ".png)\n\n";
    } else if (gp) {
      pictures += "Picture of " + v.name + " missing: " + why + "\n\n";
    }
  }
  return pictures;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Certification drop tests: runs the scene's [certification] matrix and writes a compliance report"};
  lg::cli::addVersion(app, "certify");
  std::string scenePath, outDir = "compliance", basis;
  bool plots = false, quiet = false, nominal = false;
  int threads = 0;
  lg::cli::addInputFile(app, "scene", scenePath, "scene file (TOML) with a [certification] table");
  lg::cli::addChoice(app, "--basis", basis, "replace the table's basis: part25, cs25, part23, cs23, custom",
                     {"part25", "cs25", "part23", "cs23", "custom"});
  app.add_flag("--nominal", nominal, "with an [envelope]: run the nominal point only, not every corner");
  lg::cli::addText(app, "--out", outDir, "output directory (default: compliance)");
  app.add_flag("--plots", plots, "draw one picture per case with its limits (gnuplot)");
  lg::cli::addThreads(app, threads, "the cases");
  app.add_flag("--quiet", quiet, "no table on the terminal");
  if (const int rc = lg::cli::parse(app, argc, argv); rc >= 0) return rc;

  lg::Scene scene;
  std::shared_ptr<const lg::Certification> spec;
  try {
    scene = lg::loadScene(scenePath);
    spec = matrixOf(scene, scenePath, basis);
  } catch (const lg::InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return lg::cli::kUsage;
  }
  threads = lg::cli::resolveThreads(threads);
  // The output directory exists and takes files before the first case runs.
  try {
    lg::prepareOutputDir(outDir);
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return lg::cli::kFailed;
  }
  lg::cli::installInterruptHandler();
  lg::CaseOptions opt;
  opt.record = plots;
  opt.stop = [] { return lg::cli::interrupted(); };
  std::vector<lg::CaseResult> runs;
  const auto start = std::chrono::steady_clock::now();
  const lg::Provenance prov = lg::makeProvenance("certify", argc, argv, lg::sceneInputs(scene));
  lg::Compliance c = lg::assessCompliance(scene, *spec, threads, opt, &runs, !nominal);
  c.provenanceJson = lg::provenanceJson(prov);
  c.provenanceMarkdown = lg::provenanceMarkdown(prov);
  if (!lg::cli::interrupted() && !scene.roles.struts.empty())
    c.servicing = lg::servicingCurve(scene, spec->landingMass > 0 ? spec->landingMass : lg::caseMass(scene, lg::DropCase{}));
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (lg::cli::interrupted()) {
    std::cerr << "interrupted: nothing written\n";
    return lg::cli::kInterrupted;
  }
  try {
    const std::string pictures =
        plots ? drawPictures(scene, *spec, c, runs, outDir) : "Not drawn: run `certify` with `--plots`.\n";
    if (c.servicing && c.servicing->ok) {
      lg::writeFileAtomic((fs::path(outDir) / "static_curve.csv").string(), lg::staticCurveCsv(*c.servicing));
      lg::writeFileAtomic((fs::path(outDir) / "servicing_chart.csv").string(), lg::servicingChartCsv(*c.servicing));
    }
    lg::writeFileAtomic((fs::path(outDir) / "compliance.json").string(), lg::complianceJson(c));
    lg::writeFileAtomic((fs::path(outDir) / "compliance.md").string(), lg::complianceMarkdown(c, pictures));
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return lg::cli::kFailed;
  }
  if (!quiet) {
    std::cout << lg::complianceSummary(c);
    if (c.envelope)
      std::printf("envelope: %zu points x %zu cases = %ld drops in %.1f s on %d thread%s\n", c.corners.size(),
                  c.cases.size() + c.checks.size(), c.drops, wall, threads, threads == 1 ? "" : "s");
    else if (scene.envelope.declared)
      std::printf("the nominal point only (--nominal): the scene's envelope has %zu corners\n", scene.envelope.corners().size() - 1);
    std::cout << "wrote " << outDir << "/compliance.json and compliance.md" << (plots ? " with plots" : "") << "\n";
  }
  return c.pass ? lg::cli::kOk : lg::cli::kFailed;
}
