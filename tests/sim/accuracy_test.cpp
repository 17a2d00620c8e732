// Accuracy on demand (sim/accuracy.hpp): the promise of settingForAccuracy on every shipped scene and case,
// the [solver] accuracy key and simulate --accuracy, and the work-precision data (simulate --work-precision).
#include "tests/sim/engine_support.hpp"  // sim headers, then Catch (see there)
#include "tests/sim/scene_support.hpp"

#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "sim/accuracy.hpp"

namespace {

// Every scene in data/ (a new scene there is checked too).
std::vector<std::string> shippedScenes() {
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(lgtest::sourcePath("data")))
    if (e.path().extension() == ".toml") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  return files;
}

// The reference of a scene's cases: dopri5 at rtol 1e-10, atol 1e-12.
std::vector<lg::CaseResult> referenceRuns(const lg::Scene& sc) {
  return lg::runCases(lg::withSolver(sc, lg::IntegratorKind::DormandPrince, 1e-10), sc.cases, 2);
}

int simulate(const std::string& args) {
  const std::string cmd = "'" + lgtest::binPath("simulate") + "' " + args + " >/dev/null 2>&1";
  const int st = std::system(cmd.c_str());
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

}  // namespace

TEST_CASE("accuracy on demand keeps its promise on every shipped scene and case at 1e-2, 1e-3 and 1e-4",
          "[accuracy]") {
  // The largest relative error of the seven metrics (peak load, its time, max stroke, max travel, max tyre
  // deflection, efficiency, the struts' peak force P_a,max) against the scene's own tight run is below the
  // accuracy asked for. Measured (worst over scenes and cases): 5.1e-3 at 1e-2 (seed limit, the time of its
  // flat peak: the same before ros34pw2's velocities took its continuous extension; 4.9e-3 in the nose
  // reserve before its W held the stiffness), 3.2e-4 at 1e-3 (nose limit, time of the peak), 2.2e-5 at
  // 1e-4 (seed light, time of the peak). The shipped default setting (dopri5, rtol 1e-6) is held to 1e-5
  // (measured 4.3e-7, metering pin light). P_a,max itself: 2.8e-3 at 1e-2 (telescopic free drop), 2.6e-4
  // at 1e-3 (seed medium), 1.2e-5 at 1e-4 (seed limit).
  const auto files = shippedScenes();
  REQUIRE(files.size() >= 3);
  for (const auto& file : files) {
    const lg::Scene sc = lg::loadScene(file);
    const auto ref = referenceRuns(sc);
    for (double accuracy : {1e-2, 1e-3, 1e-4, 0.0}) {
      lg::Scene run = sc;
      if (accuracy > 0) lg::applyAccuracy(run.model.settings, accuracy);
      const double promise = accuracy > 0 ? accuracy : 1e-5;
      const auto res = lg::runCases(run, run.cases, 2);
      double worst = 0;
      std::string where;
      for (size_t i = 0; i < res.size(); ++i) {
        INFO(file << ", case " << res[i].metrics.name << ": " << res[i].metrics.message);
        REQUIRE(res[i].metrics.ok);
        REQUIRE(ref[i].metrics.ok);
        const double e = lg::metricErrors(res[i].metrics, ref[i].metrics).max();
        if (e > worst) {
          worst = e;
          where = res[i].metrics.name;
        }
      }
      lgtest::report("%-28s accuracy %.0e: worst metric error %.2e (%s)", sc.name.c_str(), promise, worst, where.c_str());
      INFO(sc.name << " at accuracy " << promise << ": worst error " << worst << " in case " << where);
      CHECK(worst <= promise);
    }
  }
}

TEST_CASE("the accuracy mapping: loose accuracies take ros34pw2, tight ones dopri5, out of range is refused",
          "[accuracy]") {
  CHECK(lg::settingForAccuracy(1e-2).integrator == lg::IntegratorKind::Ros34pw2);
  CHECK(lg::settingForAccuracy(1e-3).integrator == lg::IntegratorKind::DormandPrince);
  CHECK(lg::settingForAccuracy(1e-4).integrator == lg::IntegratorKind::DormandPrince);
  // Tighter accuracy, tighter tolerance, on each branch.
  CHECK(lg::settingForAccuracy(3e-3).rtol < lg::settingForAccuracy(1e-2).rtol);
  CHECK(lg::settingForAccuracy(1e-4).rtol < lg::settingForAccuracy(1e-3).rtol);
  CHECK(lg::accuracyRule(1e-3).empty());
  CHECK(lg::accuracyRule(lg::kAccuracyMin).empty());
  CHECK(lg::accuracyRule(lg::kAccuracyMax).empty());
  CHECK(!lg::accuracyRule(0.5).empty());
  CHECK(!lg::accuracyRule(1e-9).empty());
  CHECK(!lg::accuracyRule(std::nan("")).empty());
}

TEST_CASE("the scene key solver.accuracy chooses the solver, and a bad value or a clash is bad input",
          "[accuracy][scene][input]") {
  toml::table doc = lgtest::shippedDoc("data/seed_gear.toml");
  toml::table& solver = *doc["solver"].as_table();
  for (const char* k : {"integrator", "rtol", "atol"}) solver.erase(k);
  solver.insert_or_assign("accuracy", 1e-2);
  const lg::Scene sc = lgtest::build(doc);
  const lg::AccuracySetting a = lg::settingForAccuracy(1e-2);
  CHECK(sc.model.settings.integrator == a.integrator);
  CHECK(sc.model.settings.rtol == a.rtol);
  CHECK(sc.model.settings.atol == a.atol);
  CHECK(sc.model.settings.maxStep == a.maxStep);
  CHECK(sc.model.settings.accuracy == 1e-2);
  auto message = [&](const toml::table& d) {
    try {
      lgtest::build(d, "acc.toml");
    } catch (const lg::InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  toml::table bad = doc;
  bad["solver"].as_table()->insert_or_assign("accuracy", 0.5);
  CHECK(message(bad).find("'solver.accuracy'") != std::string::npos);
  CHECK(message(bad).find("between") != std::string::npos);
  toml::table clash = doc;
  clash["solver"].as_table()->insert_or_assign("rtol", 1e-3);
  CHECK(message(clash).find("'solver.rtol'") != std::string::npos);
  // The command line: --accuracy out of range or with --rtol is bad input (exit 2, nothing written).
  lgtest::TempDir dir("acc");
  const std::string scene = "'" + lgtest::sourcePath("data/seed_gear.toml") + "'";
  CHECK(simulate(scene + " --accuracy 2 --out '" + (dir / "a") + "'") == 2);
  CHECK(simulate(scene + " --accuracy 1e-3 --rtol 1e-3 --out '" + (dir / "b") + "'") == 2);
  CHECK(!std::filesystem::exists(dir / "a"));
  CHECK(!std::filesystem::exists(dir / "b"));
  CHECK(simulate(scene + " --accuracy 1e-2 --case limit --quiet --out '" + (dir / "c") + "'") == 0);
  CHECK(std::filesystem::exists((dir / "c") + "/limit.csv"));
}

TEST_CASE("work-precision: every integrator's error falls as its tolerance tightens", "[accuracy][work-precision]") {
  const lg::Scene sc = lg::loadScene(lgtest::sourcePath("data/seed_gear.toml"));
  lg::WorkPrecisionOptions opt;
  opt.fast = true;
  opt.repetitions = 1;
  const auto points = lg::workPrecision(sc, {lgtest::findCase(sc, "limit")}, opt);
  for (const char* integ : {"dopri5", "ros34pw2", "ros2", "rk4", "euler"}) {
    std::vector<lg::WorkPrecisionPoint> p;
    for (const auto& x : points)
      if (x.integrator == integ) p.push_back(x);
    REQUIRE(p.size() >= 2);
    for (size_t i = 0; i < p.size(); ++i) {
      INFO(integ << " at " << p[i].tolerance << ": " << p[i].message);
      REQUIRE(p[i].ok);
      lgtest::report("work-precision %-9s %7.0e: peak %.2e stroke %.2e travel %.2e max %.2e, %ld evaluations", integ,
                     p[i].tolerance, p[i].errors.peakLoad, p[i].errors.stroke, p[i].errors.travel, p[i].errors.max(),
                     p[i].rhsEvaluations);
    }
    // Loosest against tightest: the largest error at least 3 times smaller (the fixed-step methods, whose
    // events land on step ends, converge at first order: rk4 1.9e-3 -> 6.1e-4, euler 1.2e-3 -> 2.4e-4).
    INFO(integ);
    CHECK(p.back().errors.max() < p.front().errors.max() / 3);
    CHECK(p.back().errors.peakLoad < p.front().errors.peakLoad);
    CHECK(p.back().rhsEvaluations > p.front().rhsEvaluations);
  }
}

TEST_CASE("simulate --work-precision writes the table for the scene's own reference", "[accuracy][work-precision][cli]") {
  lgtest::TempDir dir("wp");
  const std::string out = dir / "wp";
  REQUIRE(simulate("'" + lgtest::sourcePath("data/telescopic_gear.toml") + "' --work-precision --case limit --quiet --out '" +
                   out + "'") == 0);
  const std::string csv = lgtest::readFile(out + "/work_precision.csv");
  CHECK(csv.rfind("case,integrator,tolerance,steps,rhs_evaluations,time_per_drop_s,error_peak_load,", 0) == 0);
  CHECK(csv.find(",error_efficiency,error_strut_force,error_max,ok\n") != std::string::npos);
  for (const char* integ : {"dopri5", "ros34pw2", "ros2", "rk4", "euler"})
    CHECK(csv.find(std::string("limit,") + integ + ",") != std::string::npos);
  CHECK(std::count(csv.begin(), csv.end(), '\n') >= 20);
}
