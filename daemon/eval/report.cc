#include "daemon/eval/report.h"

#include "io/formats/output_file.h"

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <map>
#include <numeric>
#include <ostream>
#include <random>
#include <set>
#include <sstream>

namespace saccade::eval {
namespace {

constexpr float kRuleM = 0.08f;           // the paper's rule: within 8 cm of the truth
constexpr double kPoseRule = 0.1;         // ADD-S within a tenth of the model's diagonal
constexpr int kAcquireFrames = 10;        // protocol (c)'s target: found within this many frames
constexpr std::size_t kPosePoints = 400;  // model points ADD-S is measured over

// How one trial scored against its case's truth.
struct Scored {
  bool found = false;       // the 8 cm rule
  bool pose_found = false;  // the pose rule (needs a truth pose)
  int false_instances = 0;
  double translation_m = -1, rotation_deg = -1, adds_m = -1;  // of the best true instance
  float confidence = -1;
};

Scored ScoreTrial(const Trial& t, const Scene& s, const EvalModel& m,
                  const std::vector<Eigen::Vector3f>& pose_points, float diagonal_m) {
  Scored r;
  const SceneScore score = ScoreScene(t.centres, s.truth_m, kRuleM);
  r.found = score.true_positives > 0;
  r.false_instances = score.false_positives;
  for (std::size_t i = 0; i < t.instances.size(); ++i) {
    if ((t.centres[i] - s.truth_m).norm() > kRuleM || !s.truth_pose) continue;
    const Eigen::Matrix4f& pose = t.instances[i].model_to_scene;
    const double adds = SymmetricPoseDistance(pose, *s.truth_pose, pose_points);
    if (r.adds_m >= 0 && adds >= r.adds_m) continue;
    const PoseError e = ComparePoses(pose, *s.truth_pose, m.centre);
    r.adds_m = adds;
    r.translation_m = e.translation_m;
    r.rotation_deg = e.rotation_deg;
    r.confidence = t.instances[i].confidence;
    r.pose_found = adds <= kPoseRule * diagonal_m;
  }
  return r;
}

double Quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, std::size_t(q * double(v.size() - 1) + 0.5))];
}

std::string Percent(int k, int n) {
  std::ostringstream s;
  const Interval ci = WilsonInterval(k, n);
  s << k << "/" << n << " (" << std::fixed << std::setprecision(0) << (n ? 100.0 * k / n : 0.0)
    << "%, CI " << 100 * ci.low << "-" << 100 * ci.high << "%)";
  return s.str();
}

// The figures of one configuration and protocol over a subset of the cases.
struct Summary {
  int feasible = 0, found = 0, pose_found = 0;
  int infeasible = 0, infeasible_found = 0;
  int cases = 0, false_instances = 0;
  std::vector<double> ms;
  int acquired_in_target = 0, acquired = 0, false_acquisitions = 0;
  std::vector<double> frame_ms;  // protocol (c): every search frame's cost
  std::vector<double> found_ms;  // ...and per case found, the cost of its frames until then
  double FalsePerCase() const { return cases ? double(false_instances) / cases : 0; }
  double Recall() const { return feasible ? double(found) / feasible : 0; }
};

// The report of one evaluation: every trial scored once, then each table written from the scores.
class CaseReport {
 public:
  CaseReport(const std::vector<EvalConfiguration>& configs, const std::vector<EvalModel>& models,
             const std::vector<Scene>& scenes, const std::vector<std::vector<ProtocolRun>>& runs);

  void WriteSummary(const std::string& cases_file, std::ostream& md, std::ostream& out) const;
  void WriteMisses(std::ostream& md) const;
  void WriteCrossValidation(std::ostream& md) const;
  void WriteBreakdowns(std::ostream& md) const;
  void WriteReliability(std::ostream& md) const;
  void WriteInstances(std::ostream& inst) const;
  void WriteCases(std::ostream& csv) const;

 private:
  // Configuration c's protocol p over the cases `include` takes.
  template <typename Include>
  Summary Summarize(std::size_t c, std::size_t p, const Include& include) const;
  static bool All(const Scene&) { return true; }
  void WriteBreakdown(std::ostream& md, const char* title, const std::set<std::string>& keys,
                      std::string Scene::*field) const;

  const std::vector<EvalConfiguration>& configs_;
  const std::vector<EvalModel>& models_;
  const std::vector<Scene>& scenes_;
  const std::vector<std::vector<ProtocolRun>>& runs_;
  std::vector<std::vector<Eigen::Vector3f>> pose_points_;  // per model: ADD-S's points
  std::vector<float> diagonal_;                            // per model
  std::vector<std::vector<std::vector<Scored>>> scored_;   // per configuration, protocol, case
  std::set<std::string> identities_, categories_;
};

CaseReport::CaseReport(const std::vector<EvalConfiguration>& configs,
                       const std::vector<EvalModel>& models, const std::vector<Scene>& scenes,
                       const std::vector<std::vector<ProtocolRun>>& runs)
    : configs_(configs), models_(models), scenes_(scenes), runs_(runs) {
  // Per model: the points ADD-S is measured over and the model's diagonal.
  pose_points_.resize(models_.size());
  diagonal_.assign(models_.size(), 0);
  for (std::size_t m = 0; m < models_.size(); ++m) {
    std::vector<Eigen::Vector3f> finite;
    Eigen::Vector3f lo = Eigen::Vector3f::Constant(1e9f), hi = -lo;
    for (const PointT& p : models_[m].cloud.points)
      if (p.getVector3fMap().allFinite()) {
        finite.push_back(p.getVector3fMap());
        lo = lo.cwiseMin(finite.back());
        hi = hi.cwiseMax(finite.back());
      }
    const std::size_t step = std::max<std::size_t>(1, finite.size() / kPosePoints);
    for (std::size_t i = 0; i < finite.size(); i += step) pose_points_[m].push_back(finite[i]);
    diagonal_[m] = finite.empty() ? 0 : (hi - lo).norm();
  }

  // Every trial scored, and summaries over any subset of the cases.
  scored_.resize(runs_.size());
  for (std::size_t c = 0; c < runs_.size(); ++c)
    for (const ProtocolRun& run : runs_[c]) {
      scored_[c].emplace_back();
      for (std::size_t i = 0; i < scenes_.size(); ++i) {
        const std::size_t m = scenes_[i].model;
        scored_[c].back().push_back(
            ScoreTrial(run.trials[i], scenes_[i], models_[m], pose_points_[m], diagonal_[m]));
      }
    }
  for (const Scene& s : scenes_) {
    identities_.insert(s.identity);
    if (!s.category.empty()) categories_.insert(s.category);
  }
}

template <typename Include>
Summary CaseReport::Summarize(std::size_t c, std::size_t p, const Include& include) const {
  Summary s;
  const ProtocolRun& run = runs_[c][p];
  for (std::size_t i = 0; i < scenes_.size(); ++i) {
    if (!include(scenes_[i])) continue;
    const Scored& r = scored_[c][p][i];
    ++s.cases;
    s.ms.push_back(run.trials[i].ms);
    bool found = r.found;
    int false_instances = r.false_instances;
    if (run.protocol == Protocol::kAcquisition) {
      const Acquisition& a = run.acquisitions[i];
      found = a.frames > 0;
      false_instances = a.false_instances;
      s.acquired_in_target += scenes_[i].feasible && found && a.frames <= kAcquireFrames;
      s.acquired += scenes_[i].feasible && found;
      s.false_acquisitions += a.false_locks > 0;
      s.frame_ms.insert(s.frame_ms.end(), a.frame_ms.begin(), a.frame_ms.end());
      if (found) s.found_ms.push_back(std::accumulate(a.frame_ms.begin(), a.frame_ms.end(), 0.0));
    }
    s.false_instances += false_instances;
    if (scenes_[i].feasible) {
      ++s.feasible;
      s.found += found;
      s.pose_found += r.pose_found;
    } else {
      ++s.infeasible;
      s.infeasible_found += found;
    }
  }
  return s;
}

void CaseReport::WriteSummary(const std::string& cases_file, std::ostream& md,
                              std::ostream& out) const {
  int feasible = 0;
  for (const Scene& s : scenes_) feasible += s.feasible;
  md << "# Cross-capture evaluation of " << cases_file << "\n\n"
     << scenes_.size() << " cases (" << feasible << " feasible, " << scenes_.size() - feasible
     << " infeasible: reported apart), " << identities_.size() << " identities. Recall counts "
     << "the feasible cases found by the paper's 8 cm rule, with its 95% Wilson interval; the "
     << "pose rule asks for ADD-S (the mean distance of the model's points to the nearest point "
     << "of the model at its true pose) within a tenth of the model's diagonal. False instances "
     << "are counted over every case. Protocol (a): the fovea on the object; (b): one frame, the "
     << "fovea 15 cm away in a seeded random direction; (c): the attention loop from (0, 0, 1) m, "
     << "at most 30 frames (found: within " << kAcquireFrames << " frames).\n\n";
  md << "| configuration | protocol | recall, feasible (8 cm rule) | pose rule | infeasible found "
        "| false instances / case | ms median | ms p90 |\n|---|---|---|---|---|---|---|---|\n";
  out << std::fixed;
  for (std::size_t c = 0; c < runs_.size(); ++c)
    for (std::size_t p = 0; p < runs_[c].size(); ++p) {
      const Summary s = Summarize(c, p, All);
      const bool acquisition = runs_[c][p].protocol == Protocol::kAcquisition;
      const std::string recall = acquisition ? Percent(s.acquired_in_target, s.feasible) + " in " +
                                                   std::to_string(kAcquireFrames) + " frames, " +
                                                   std::to_string(s.acquired) + " in 30"
                                             : Percent(s.found, s.feasible);
      std::ostringstream row;
      row << std::fixed << std::setprecision(3) << s.FalsePerCase();
      if (acquisition)
        row << " seen; " << s.false_acquisitions << " of " << s.cases
            << " cases locked onto a false one first; frame p99 " << std::setprecision(1)
            << Quantile(s.frame_ms, 0.99) << " ms; found after p50 " << Quantile(s.found_ms, 0.5)
            << " / p90 " << Quantile(s.found_ms, 0.9) << " ms of search";
      md << "| " << configs_[c].name << " | " << ProtocolName(runs_[c][p].protocol) << " | "
         << recall << " | " << (acquisition ? "-" : Percent(s.pose_found, s.feasible)) << " | "
         << s.infeasible_found << "/" << s.infeasible << " | " << row.str() << " | "
         << std::setprecision(1) << Quantile(s.ms, 0.5) << " | " << Quantile(s.ms, 0.9) << " |\n";
      out << "  " << std::left << std::setw(24) << configs_[c].name << std::right << " ("
          << ProtocolName(runs_[c][p].protocol) << ") recall " << recall << ", false/case "
          << row.str() << ", median " << std::setprecision(1) << Quantile(s.ms, 0.5) << " ms\n";
    }
}

// Where the misses of protocol (a) were lost.
void CaseReport::WriteMisses(std::ostream& md) const {
  md << "\n## Where each feasible miss was lost (protocol a)\n\n| configuration";
  const CaseStage stages[] = {CaseStage::kFound,        CaseStage::kNoCorrectCorrespondence,
                              CaseStage::kNoHypothesis, CaseStage::kNotVerified,
                              CaseStage::kRejected,     CaseStage::kOutranked};
  for (CaseStage st : stages) md << " | " << CaseStageName(st);
  md << " |\n|---";
  for (std::size_t i = 0; i < std::size(stages); ++i) md << "|---";
  md << "|\n";
  std::map<std::string, int> rejected_by;  // per configuration and verdict, for the note below
  for (std::size_t c = 0; c < runs_.size(); ++c)
    for (std::size_t p = 0; p < runs_[c].size(); ++p) {
      if (runs_[c][p].protocol != Protocol::kOnObject) continue;
      std::map<CaseStage, int> count;
      for (std::size_t i = 0; i < scenes_.size(); ++i) {
        if (!scenes_[i].feasible) continue;
        const CaseEvidence& e = runs_[c][p].trials[i].evidence;
        const CaseStage st = DiagnoseCase(e, scenes_[i].truth_pose.has_value());
        ++count[st];
        if (st == CaseStage::kRejected)
          for (Verdict v : e.true_hypotheses)
            ++rejected_by[configs_[c].name + ": " + VerdictName(v)];
      }
      md << "| " << configs_[c].name;
      for (CaseStage st : stages) md << " | " << count[st];
      md << " |\n";
    }
  if (!rejected_by.empty()) {
    md << "\nVerdicts on the true hypotheses of the rejected cases:";
    for (const auto& [key, n] : rejected_by) md << " " << key << " " << n << ";";
    md << "\n";
  }
}

// Cross-validation across objects: identities in two halves (a seeded shuffle), the
// configuration chosen on one half (recall minus false instances per case, protocol a),
// reported on the other.
void CaseReport::WriteCrossValidation(std::ostream& md) const {
  std::vector<std::string> ids(identities_.begin(), identities_.end());
  std::shuffle(ids.begin(), ids.end(), std::mt19937(1));
  const std::set<std::string> half_a(ids.begin(), ids.begin() + long(ids.size() / 2));
  md << "\n## Cross-validation across objects (protocol a)\n\nIdentities split in two halves "
        "by a seeded shuffle (seed 1). Half A: ";
  for (const std::string& id : half_a) md << id << " ";
  md << "\n\n| chosen on | configuration | its recall there | on the other half | full set |\n"
        "|---|---|---|---|---|\n";
  for (int half = 0; half < 2; ++half) {
    const auto on = [&, half](const Scene& s) { return (half_a.count(s.identity) > 0) == !half; };
    const auto other = [&, half](const Scene& s) {
      return (half_a.count(s.identity) > 0) == !!half;
    };
    std::size_t best_c = 0, best_p = 0;
    double best = -1e9;
    for (std::size_t c = 0; c < runs_.size(); ++c)
      for (std::size_t p = 0; p < runs_[c].size(); ++p) {
        if (runs_[c][p].protocol != Protocol::kOnObject) continue;
        const Summary s = Summarize(c, p, on);
        if (s.Recall() - s.FalsePerCase() > best) {
          best = s.Recall() - s.FalsePerCase();
          best_c = c, best_p = p;
        }
      }
    if (runs_.empty() || runs_[best_c].empty()) break;
    const Summary a = Summarize(best_c, best_p, on), b = Summarize(best_c, best_p, other),
                  f = Summarize(best_c, best_p, All);
    md << "| half " << (half ? "B" : "A") << " | " << configs_[best_c].name << " | "
       << Percent(a.found, a.feasible) << " | " << Percent(b.found, b.feasible) << ", "
       << std::setprecision(3) << b.FalsePerCase() << " false/case | "
       << Percent(f.found, f.feasible) << " |\n";
  }
}

// Per object and per category: found / feasible, protocol (a), every configuration.
void CaseReport::WriteBreakdown(std::ostream& md, const char* title,
                                const std::set<std::string>& keys,
                                std::string Scene::*field) const {
  md << "\n## Per " << title << " (protocol a: found / feasible, false instances)\n\n| " << title;
  for (const auto& c : configs_) md << " | " << c.name;
  md << " |\n|---";
  for (std::size_t i = 0; i < configs_.size(); ++i) md << "|---";
  md << "|\n";
  for (const std::string& key : keys) {
    md << "| " << key;
    for (std::size_t c = 0; c < runs_.size(); ++c)
      for (std::size_t p = 0; p < runs_[c].size(); ++p) {
        if (runs_[c][p].protocol != Protocol::kOnObject) continue;
        const Summary s = Summarize(c, p, [&](const Scene& sc) { return sc.*field == key; });
        md << " | " << s.found << "/" << s.feasible << ", " << s.false_instances;
      }
    md << " |\n";
  }
}

void CaseReport::WriteBreakdowns(std::ostream& md) const {
  WriteBreakdown(md, "object", identities_, &Scene::identity);
  if (!categories_.empty()) WriteBreakdown(md, "category", categories_, &Scene::category);
}

// Reliability of the confidence: per bin of confidence, the share of instances that are true.
void CaseReport::WriteReliability(std::ostream& md) const {
  md << "\n## Reliability of the confidence (protocol a, every reported instance)\n\n"
        "| configuration | confidence | instances | true | share true |\n|---|---|---|---|---|\n";
  for (std::size_t c = 0; c < runs_.size(); ++c)
    for (const ProtocolRun& run : runs_[c]) {
      if (run.protocol != Protocol::kOnObject) continue;
      const double edges[] = {0.0, 0.3, 0.5, 0.7, 0.8, 0.9, 1.01};
      for (std::size_t b = 0; b + 1 < std::size(edges); ++b) {
        int n = 0, t = 0;
        for (std::size_t i = 0; i < scenes_.size(); ++i)
          for (std::size_t k = 0; k < run.trials[i].instances.size(); ++k) {
            const float conf = run.trials[i].instances[k].confidence;
            if (conf < edges[b] || conf >= edges[b + 1]) continue;
            ++n;
            t += (run.trials[i].centres[k] - scenes_[i].truth_m).norm() <= kRuleM;
          }
        if (n == 0) continue;
        md << "| " << configs_[c].name << " | " << std::setprecision(1) << edges[b] << "-"
           << std::min(1.0, edges[b + 1]) << " | " << n << " | " << t << " | " << Percent(t, n)
           << " |\n";
      }
    }
}

// Every reported instance with its figures: what a confidence is calibrated on.
void CaseReport::WriteInstances(std::ostream& inst) const {
  inst << "configuration,protocol,case,identity,feasible,rank,true,votes,fitness,coverage,"
          "colour_agreement,confidence,texture,texture_agreement,continued\n";
  for (std::size_t c = 0; c < runs_.size(); ++c)
    for (const ProtocolRun& run : runs_[c])
      for (std::size_t i = 0; i < scenes_.size(); ++i)
        for (std::size_t k = 0; k < run.trials[i].instances.size(); ++k) {
          const Detection& d = run.trials[i].instances[k];
          inst << configs_[c].name << ',' << ProtocolName(run.protocol) << ',' << scenes_[i].name
               << ',' << scenes_[i].identity << ',' << scenes_[i].feasible << ',' << k << ','
               << ((run.trials[i].centres[k] - scenes_[i].truth_m).norm() <= kRuleM) << ','
               << d.votes << ',' << d.fitness << ',' << d.coverage << ',' << d.colour_agreement
               << ',' << d.confidence << ','
               << (k < run.trials[i].texture.size() ? run.trials[i].texture[k] : -1) << ','
               << d.texture_agreement << ',' << d.continued << "\n";
        }
}

// Every case under every configuration and protocol.
void CaseReport::WriteCases(std::ostream& csv) const {
  csv << "configuration,protocol,case,identity,category,feasible,found,pose_found,"
         "false_instances,ms,translation_err_m,rotation_err_deg,adds_m,diagonal_m,confidence,"
         "stage,correct_correspondences,hypotheses,acquire_frames,acquire_false,false_seen,"
         "candidate_rank,frame_ms_max,first_lock_frame,first_lock_why\n";
  for (std::size_t c = 0; c < runs_.size(); ++c)
    for (std::size_t p = 0; p < runs_[c].size(); ++p)
      for (std::size_t i = 0; i < scenes_.size(); ++i) {
        const ProtocolRun& run = runs_[c][p];
        const Scene& s = scenes_[i];
        const Scored& r = scored_[c][p][i];
        const Trial& t = run.trials[i];
        csv << configs_[c].name << ',' << ProtocolName(run.protocol) << ',' << s.name << ','
            << s.identity << ",\"" << s.category << "\"," << s.feasible << ',' << r.found << ','
            << r.pose_found << ',' << r.false_instances << ',' << t.ms << ',' << r.translation_m
            << ',' << r.rotation_deg << ',' << r.adds_m << ',' << diagonal_[s.model] << ','
            << r.confidence << ','
            << CaseStageName(DiagnoseCase(t.evidence, s.truth_pose.has_value())) << ','
            << t.evidence.correct_correspondences << ',' << t.stats.hypotheses << ',';
        if (run.protocol == Protocol::kAcquisition) {
          const Acquisition& a = run.acquisitions[i];
          csv << a.frames << ',' << a.false_locks << ',' << a.false_instances << ','
              << a.candidate_rank << ','
              << (a.frame_ms.empty() ? 0.0
                                     : *std::max_element(a.frame_ms.begin(), a.frame_ms.end()))
              << ',' << a.first_lock_frame << ',' << a.first_lock_why;
        } else {
          csv << ",,,,,,";
        }
        csv << "\n";
      }
}

}  // namespace

const char* ProtocolName(Protocol p) {
  switch (p) {
    case Protocol::kOnObject:
      return "a";
    case Protocol::kOffObject:
      return "b";
    case Protocol::kAcquisition:
      return "c";
  }
  return "?";
}

bool WriteCaseReport(const std::string& cases_file, const std::vector<EvalConfiguration>& configs,
                     const std::vector<EvalModel>& models, const std::vector<Scene>& scenes,
                     const std::vector<std::vector<ProtocolRun>>& runs,
                     const std::filesystem::path& dir, std::ostream& out, std::string* error) {
  const CaseReport report(configs, models, scenes, runs);
  TextFile md(dir / "report.md");
  md << std::fixed;  // one stream for every table: each sets the precision it prints with
  report.WriteSummary(cases_file, md, out);
  report.WriteMisses(md);
  report.WriteCrossValidation(md);
  report.WriteBreakdowns(md);
  report.WriteReliability(md);
  TextFile inst(dir / "instances.csv");
  report.WriteInstances(inst);
  TextFile csv(dir / "cases.csv");
  report.WriteCases(csv);
  for (const TextFile* file : {&md, &inst, &csv})
    if (!file->Commit(error)) return false;
  return true;
}

}  // namespace saccade::eval
