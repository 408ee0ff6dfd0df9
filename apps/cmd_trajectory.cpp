// SPDX-License-Identifier: MIT
// Subcommands on trajectories: eval, deadreckon, convert.
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "cli_common.h"
#include "eval_plot_data.h"
#include "graphslam/eval/trajectory_metrics.h"
#include "graphslam/init/dead_reckoning.h"
#include "graphslam/io/g2o.h"
#include "graphslam/io/relative_poses.h"
#include "graphslam/io/trajectory.h"
#include "graphslam/support/error.h"
#include "graphslam/support/file_util.h"
#include "input.h"
#include "output_set.h"
#include "plotting.h"
#include "view_output.h"

namespace graphslam::apps {

using namespace graphslam::eval;
using namespace graphslam::io;

namespace {

constexpr double kRadToDeg = 57.295779513082320876;

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

/// "auto" picks by extension: .g2o, .kitti, anything else TUM.
std::string trajectoryFormat(const std::string& path, const std::string& format) {
  if (format != "auto") {
    if (format != "tum" && format != "kitti" && format != "g2o") {
      throw UsageError("trajectory format must be auto, tum, kitti or g2o, not '" + format + "'");
    }
    return format;
  }
  if (endsWith(path, ".g2o")) return "g2o";
  if (endsWith(path, ".kitti")) return "kitti";
  return "tum";
}

/// A trajectory from a file: a TUM or KITTI trajectory, or a graph's poses (.g2o and every
/// other graph format of the registry; trajectoryFromGraph).
Trajectory loadTrajectory(const std::string& path, const std::string& format,
                          const Registries& reg) {
  const std::string f = trajectoryFormat(path, format);
  if (f == "g2o") return io::trajectoryFromGraph(loadInput(path, reg).graph);
  io::Source source = io::Source::open(path);
  return reg.formats.find<Trajectory>(f)->read(source, {});
}

/// Writes `t` as TUM or KITTI (by --format, else by the name); a name that says neither is
/// refused rather than guessed.
void saveTrajectory(const std::string& path, const Trajectory& t, const std::string& format,
                    const Registries& reg) {
  const io::Format<Trajectory>* f = format == "auto" ? reg.formats.forOutput<Trajectory>(path)
                                                     : reg.formats.find<Trajectory>(format);
  if (format == "g2o" || (format == "auto" && endsWith(path, ".g2o"))) {
    throw UsageError("write trajectories as TUM or KITTI, not .g2o");
  }
  if (!f) {
    throw UsageError("cannot tell the trajectory format of '" + path +
                     "' from its name: end it in .tum, .txt or .kitti, or give --format tum|kitti");
  }
  if (t.empty())
    throw InputError(path + ": no poses to write (the graph has no SE(2) or SE(3) pose)");
  support::writeFileAtomically(path, [&](std::ostream& out) { f->write(t, out, {}); });
}

PoseRelation parseRelation(const std::string& r) {
  PoseRelation relation{};
  if (!poseRelationFromName(r, &relation)) {
    throw UsageError(std::string("--pose-relation must be ") + kPoseRelationNames + ", not '" + r +
                     "'");
  }
  return relation;
}

std::string relationTitle(PoseRelation r) {
  switch (r) {
    case PoseRelation::kTranslationPart:
      return "translation part (m)";
    case PoseRelation::kRotationPart:
      return "rotation part (unit-less)";
    case PoseRelation::kRotationAngleDeg:
      return "rotation angle in degrees (deg)";
    case PoseRelation::kRotationAngleRad:
      return "rotation angle in radians (rad)";
    case PoseRelation::kFullTransformation:
      return "full transformation (unit-less)";
    case PoseRelation::kPointDistance:
      return "point distance (m)";
    case PoseRelation::kPointDistanceErrorRatio:
      return "point distance error ratio (%)";
  }
  return "?";
}

DeltaUnit parseUnit(const std::string& u) {
  if (u == "f") return DeltaUnit::kFrames;
  if (u == "m") return DeltaUnit::kMeters;
  if (u == "rad") return DeltaUnit::kRadians;
  if (u == "deg") return DeltaUnit::kDegrees;
  throw UsageError("--delta-unit must be f, m, rad or deg, not '" + u + "'");
}

std::string statsTable(const ErrorStatistics& s) {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "       max\t%.6f\n      mean\t%.6f\n    median\t%.6f\n       min\t%.6f\n"
                "      rmse\t%.6f\n       sse\t%.6f\n       std\t%.6f\n",
                s.max, s.mean, s.median, s.min, s.rmse, s.sse, s.std_dev);
  return buf;
}

std::string jsonNumber(double x) { return std::isfinite(x) ? support::formatDouble(x) : "null"; }

/// The options of graphslam eval.
struct EvalOptions {
  std::string metric, ref_path, est_path, relation = "trans_part", ref_format = "auto",
                                          est_format = "auto";
  std::string save, plot_dir, unit = "f", view;
  std::vector<std::string> plot_with;  // more trajectories for the trajectory plot
  std::vector<std::string> plugins;    // types of a graph input's custom vertices
  double t_max_diff = 0.01, t_offset = 0.0, delta = 1.0;
  int n_to_align = -1;
  bool align = false, correct_scale = false, align_origin = false, all_pairs = false;
};

void declareEvalOptions(po::options_description& desc, EvalOptions& o) {
  desc.add_options()("help,h", "show this help")("metric", po::value(&o.metric), "ape or rpe")(
      "ref", po::value(&o.ref_path), "reference trajectory (TUM, KITTI or .g2o)")(
      "est", po::value(&o.est_path), "estimated trajectory (TUM, KITTI or .g2o)")(
      "pose-relation,r", po::value(&o.relation)->default_value("trans_part"),
      "trans_part, rot_part, angle_deg, angle_rad, full, point_distance, "
      "point_distance_error_ratio")("align,a", "SE(3) Umeyama alignment")(
      "correct-scale,s", "correct the scale (Sim(3) with --align, scale only without)")(
      "align-origin", "align the first poses")("n-to-align",
                                               po::value(&o.n_to_align)->default_value(-1),
                                               "use only the first N poses for alignment")(
      "t-max-diff", doubleValue(&o.t_max_diff, 0.01),
      "maximum timestamp difference for association (s)")(
      "t-offset", po::value(&o.t_offset)->default_value(0.0),
      "offset added to the estimate's timestamps (s)")(
      "delta,d", po::value(&o.delta)->default_value(1.0), "RPE: delta between compared poses")(
      "delta-unit,u", po::value(&o.unit)->default_value("f"), "RPE: f (frames), m, rad, deg")(
      "all-pairs", "RPE: use all pairs with the given delta, not consecutive ones")(
      "ref-format", po::value(&o.ref_format)->default_value("auto"), "auto, tum, kitti or g2o")(
      "est-format", po::value(&o.est_format)->default_value("auto"), "auto, tum, kitti or g2o")(
      "save-results", po::value(&o.save), "write the result as .json or .csv")(
      "plot", po::value(&o.plot_dir), "write PNG plots into this directory (it must exist)")(
      "view", po::value(&o.view),
      "ape: write a self-contained web page of the aligned estimate coloured by its error per "
      "pose over the reference here (docs/VIEW.md)")(
      "plot-with", po::value(&o.plot_with)->composing(),
      "also draw this trajectory (all its poses, as read) in the trajectory plot (repeatable)")(
      "plugin", po::value(&o.plugins)->composing(),
      "load types from this shared library to read a graph input (repeatable)");
}

/// Parses and checks the options; false after --help.
bool parseEvalOptions(const std::vector<std::string>& args, EvalOptions& o) {
  po::options_description desc("options");
  declareEvalOptions(desc, o);
  po::positional_options_description pos;
  pos.add("metric", 1).add("ref", 1).add("est", 1);
  const auto vm = parse(args, desc, &pos);
  if (vm.count("help")) {
    printHelp(
        "usage: graphslam eval ape|rpe REF EST [options]\n"
        "Absolute / relative pose error with evo's definitions and statistics.",
        desc);
    return false;
  }
  o.align = vm.count("align") != 0;
  o.correct_scale = vm.count("correct-scale") != 0;
  o.align_origin = vm.count("align-origin") != 0;
  o.all_pairs = vm.count("all-pairs") != 0;
  if (o.metric != "ape" && o.metric != "rpe") throw UsageError("the metric must be ape or rpe");
  if (o.ref_path.empty() || o.est_path.empty()) throw UsageError("eval needs REF and EST");
  if (!o.plot_with.empty() && o.plot_dir.empty()) throw UsageError("--plot-with needs --plot DIR");
  if (!o.view.empty() && o.metric != "ape") throw UsageError("--view draws the APE: use eval ape");
  return true;
}

/// The errors of a metric, the statistics and the poses compared.
struct EvalResult {
  std::vector<double> errors;
  std::vector<std::string> labels;  // per error: timestamp of the (second) pose it belongs to
  ErrorStatistics stats;
  Trajectory ref_used, est_used;
  UmeyamaResult umeyama;  // the alignment applied to the estimate
  Eigen::Isometry3d origin_transform = Eigen::Isometry3d::Identity();
  double seconds = 0.0;
};

AlignmentOptions alignmentOf(const EvalOptions& o) {
  AlignmentOptions align;
  const bool a = o.align, s = o.correct_scale;
  align.mode = a ? (s ? AlignmentMode::kSim3 : AlignmentMode::kSE3)
                 : (s ? AlignmentMode::kScaleOnly : AlignmentMode::kNone);
  align.align_origin = o.align_origin;
  align.num_poses = o.n_to_align;
  return align;
}

/// Computes APE or RPE; `associate`: by timestamps (not for KITTI files, which have none).
EvalResult evaluate(const EvalOptions& o, const Trajectory& ref, const Trajectory& est,
                    const AlignmentOptions& align, PoseRelation rel, bool associate) {
  AssociationOptions assoc;
  assoc.max_diff = o.t_max_diff;
  assoc.offset_2 = o.t_offset;
  const auto t0 = std::chrono::steady_clock::now();
  EvalResult e;
  auto common = [&](auto& opt) {
    opt.pose_relation = rel;
    opt.associate = associate;
    opt.association = assoc;
    opt.alignment = align;
  };
  auto take = [&](const auto& r) {
    e.errors = r.errors;
    e.stats = r.statistics;
    e.ref_used = r.reference;
    e.est_used = r.estimate;
    e.umeyama = r.umeyama;
    e.origin_transform = r.origin_transform;
  };
  if (o.metric == "ape") {
    ApeOptions opt;
    common(opt);
    const ApeResult r = computeApe(ref, est, opt);
    take(r);
    for (std::size_t i = 0; i < r.reference.size(); ++i)
      e.labels.push_back(support::formatDouble(r.reference.timestamp(i)));
  } else {
    RpeOptions opt;
    common(opt);
    opt.delta = o.delta;
    opt.delta_unit = parseUnit(o.unit);
    opt.all_pairs = o.all_pairs;
    const RpeResult r = computeRpe(ref, est, opt);
    take(r);
    for (const auto& [i, j] : r.id_pairs)
      e.labels.push_back(support::formatDouble(r.reference.timestamp(j)));
  }
  e.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return e;
}

std::string alignmentTitle(const AlignmentOptions& align) {
  std::string mode = "(not aligned)";
  if (align.mode == AlignmentMode::kSE3) mode = "(with SE(3) Umeyama alignment)";
  if (align.mode == AlignmentMode::kSim3) mode = "(with Sim(3) Umeyama alignment)";
  if (align.mode == AlignmentMode::kScaleOnly) mode = "(scale corrected)";
  if (align.align_origin) mode += " (with origin alignment)";
  return mode;
}

void writeErrorsCsv(const std::string& path, const EvalResult& e) {
  support::writeFileAtomically(path, [&](std::ostream& out) {
    out << "t,error\n";
    for (std::size_t i = 0; i < e.errors.size(); ++i)
      out << e.labels[i] << ',' << support::formatDouble(e.errors[i]) << '\n';
  });
}

void writeErrorsJson(const std::string& path, const std::string& metric, const std::string& title,
                     const std::string& mode, const EvalResult& e) {
  const ErrorStatistics& stats = e.stats;
  support::writeFileAtomically(path, [&](std::ostream& out) {
    out << "{\n  \"metric\": \"" << metric << "\",\n  \"title\": \"" << title
        << "\",\n  \"alignment\": \"" << mode
        << "\",\n  \"statistics\": {\"max\": " << jsonNumber(stats.max)
        << ", \"mean\": " << jsonNumber(stats.mean) << ", \"median\": " << jsonNumber(stats.median)
        << ", \"min\": " << jsonNumber(stats.min) << ", \"rmse\": " << jsonNumber(stats.rmse)
        << ", \"sse\": " << jsonNumber(stats.sse) << ", \"std\": " << jsonNumber(stats.std_dev)
        << "},\n  \"timestamps\": [";
    for (std::size_t i = 0; i < e.labels.size(); ++i) out << (i ? ", " : "") << e.labels[i];
    out << "],\n  \"errors\": [";
    for (std::size_t i = 0; i < e.errors.size(); ++i)
      out << (i ? ", " : "") << jsonNumber(e.errors[i]);
    out << "]\n}\n";
  });
}

/// --save-results: JSON or CSV by the file's extension.
void saveResults(const std::string& save, const std::string& metric, const std::string& title,
                 const std::string& mode, const EvalResult& e) {
  if (endsWith(save, ".json")) {
    writeErrorsJson(save, metric, title, mode, e);
  } else if (endsWith(save, ".csv")) {
    writeErrorsCsv(save, e);
  } else {
    throw UsageError("--save-results must end in .json or .csv");
  }
}

std::string baseName(const std::string& path) {
  return std::filesystem::path(path).filename().string();
}

void plotEval(const EvalOptions& o, const std::string& title, const std::string& unit,
              const EvalResult& e, const Trajectory& est, const std::vector<Trajectory>& extra) {
  const std::string stem = o.plot_dir + "/" + o.metric;
  std::vector<std::string> files = {"_reference.csv", "_estimate.csv",     "_estimate_all.csv",
                                    "_errors.csv",    "_trajectories.png", "_error.png",
                                    "_error_map.png"};
  std::vector<std::string> args = {
      o.plot_dir, o.metric,
      title + "\n" + baseName(o.est_path) + " against " + baseName(o.ref_path), unit,
      baseName(o.est_path)};
  for (std::size_t k = 0; k < extra.size(); ++k) {
    files.push_back("_with" + std::to_string(k) + ".csv");
    args.push_back(baseName(o.plot_with[k]));
  }
  try {
    writePositionsCsv(stem + "_reference.csv", e.ref_used);
    writePositionsCsv(stem + "_estimate.csv", e.est_used);
    writeAlignedPositionsCsv(stem + "_estimate_all.csv", est, e.umeyama, e.origin_transform);
    for (std::size_t k = 0; k < extra.size(); ++k) {
      writePositionsCsv(stem + "_with" + std::to_string(k) + ".csv", extra[k]);
    }
    writeErrorsCsv(stem + "_errors.csv", e);
    runPlotScript("plot_eval.py", args);
  } catch (...) {  // all or nothing: none of the plot's files stays
    for (const auto& end : files) std::remove((stem + end).c_str());
    throw;
  }
  std::printf("plots: %s_trajectories.png, %s_error.png, %s_error_map.png\n", stem.c_str(),
              stem.c_str(), stem.c_str());
}

}  // namespace

// ---------------------------------------------------------------------------------------
// eval

int cmdEval(const std::vector<std::string>& args) {
  EvalOptions o;
  if (!parseEvalOptions(args, o)) return kExitOk;
  // Outputs are checked before the work and written all or nothing.
  if (!o.save.empty() && !endsWith(o.save, ".json") && !endsWith(o.save, ".csv")) {
    throw UsageError("--save-results must end in .json or .csv");
  }
  OutputSet outputs({o.save, o.view}, {o.ref_path, o.est_path});
  if (!o.plot_dir.empty()) {
    std::error_code ec;
    if (!std::filesystem::is_directory(o.plot_dir, ec)) {
      throw UsageError(std::filesystem::exists(o.plot_dir, ec)
                           ? "--plot: " + o.plot_dir + " is a file, not a folder"
                           : "--plot: the folder " + o.plot_dir + " does not exist");
    }
    if (::access(o.plot_dir.c_str(), W_OK) != 0) {
      throw UsageError("--plot: cannot write in " + o.plot_dir + ": " + std::strerror(errno));
    }
    if (findPlotPython().empty()) {
      throw UsageError(
          "--plot needs Python 3 with matplotlib, and none was found (tried "
          "$GRAPHSLAM_PYTHON, /usr/bin/python3, python3)");
    }
  }
  // Plugins (GRAPHSLAM_PLUGIN_PATH) are loaded only to read a graph: trajectories need none,
  // and a broken plugin library does not stop their evaluation.
  Registries reg;
  host::registerBuiltins(reg);
  if (trajectoryFormat(o.ref_path, o.ref_format) == "g2o" ||
      trajectoryFormat(o.est_path, o.est_format) == "g2o" || !o.plugins.empty()) {
    host::loadPlugins(reg, o.plugins);
  }
  const Trajectory ref = loadTrajectory(o.ref_path, o.ref_format, reg);
  const Trajectory est = loadTrajectory(o.est_path, o.est_format, reg);
  std::vector<Trajectory> extra;  // --plot-with, read before the work
  for (const auto& path : o.plot_with) extra.push_back(loadTrajectory(path, "auto", reg));
  const bool kitti = trajectoryFormat(o.ref_path, o.ref_format) == "kitti" ||
                     trajectoryFormat(o.est_path, o.est_format) == "kitti";
  if (kitti && ref.size() != est.size()) {
    throw InputError(
        "KITTI trajectories have no timestamps to pair their poses by, so both "
        "need the same number of poses: " +
        o.ref_path + " has " + std::to_string(ref.size()) + ", " + o.est_path + " has " +
        std::to_string(est.size()));
  }
  const AlignmentOptions align = alignmentOf(o);
  const PoseRelation rel = parseRelation(o.relation);
  const EvalResult e = evaluate(o, ref, est, align, rel, !kitti);

  const std::string mode = alignmentTitle(align);
  std::string title =
      (o.metric == "ape" ? "APE" : "RPE") + std::string(" w.r.t. ") + relationTitle(rel);
  if (o.metric == "rpe") title += ", delta " + support::formatDouble(o.delta) + " " + o.unit;
  std::printf("%s\n%s\n\n%s\n%zu poses compared, %zu errors, %.6f s\n", title.c_str(), mode.c_str(),
              statsTable(e.stats).c_str(), e.ref_used.size(), e.errors.size(), e.seconds);
  outputs.writeAll([&] {
    if (!o.save.empty()) saveResults(outputs.staged(o.save), o.metric, title, mode, e);
    if (!o.plot_dir.empty()) {
      plotEval(o, title + " " + mode, unitOf(relationTitle(rel)), e, est, extra);
    }
    if (!o.view.empty()) {
      writeTrajectoryView(outputs.staged(o.view), e.ref_used, e.est_used, e.errors, reg,
                          std::filesystem::path(o.est_path).filename().string(),
                          {{"metric", title},
                           {"alignment", mode},
                           {"rmse", support::formatDouble(e.stats.rmse)},
                           {"max", support::formatDouble(e.stats.max)}});
      std::printf("wrote %s\n", o.view.c_str());
    }
    outputs.commit();
    return kExitOk;
  });
  if (!o.save.empty()) std::printf("wrote %s\n", o.save.c_str());
  return kExitOk;
}

// ---------------------------------------------------------------------------------------
// deadreckon

int cmdDeadreckon(const std::vector<std::string>& args) {
  std::string input, output, format = "auto", from = "auto";
  std::vector<std::string> plugins;
  po::options_description desc("options");
  desc.add_options()("help,h", "show this help")(
      "input", po::value(&input),
      "3xN relative-pose matrix file, or a pose graph (.g2o, TORO, iSAM)")(
      "output,o", po::value(&output), "write the trajectory (TUM, or KITTI for .kitti)")(
      "format", po::value(&format)->default_value("auto"), "output format: auto, tum or kitti")(
      "from", po::value(&from)->default_value("auto"),
      "input format: auto (from its name and content), g2o, toro, isam or matrix")(
      "plugin", po::value(&plugins)->composing(),
      "load types from this shared library (repeatable)");
  po::positional_options_description pos;
  pos.add("input", 1);
  const auto vm = parse(args, desc, &pos);
  if (vm.count("help")) {
    printHelp(
        "usage: graphslam deadreckon IN [-o OUT.tum] [--from FORMAT] [--plugin LIB]...\n"
        "Composes relative SE(2) poses from the identity (a 3xN matrix, column k = (dx, dy, "
        "dtheta)\n"
        "of T_k^-1 T_k+1), or the EDGE_SE2 i -> i+1 chain of a pose graph, into a trajectory.\n"
        "A graph's chain starts at the first pose's estimate; in a file without vertex lines "
        "the\n"
        "poses are created from the edges and the chain starts at the identity.",
        desc);
    return kExitOk;
  }
  if (input.empty()) throw UsageError("deadreckon needs an input file");
  Registries reg;
  loadRegistries(reg, plugins);
  checkGraphFormat(from, reg);
  io::Source source = io::Source::open(input);
  const std::string format_name =
      from == "auto" ? reg.formats.detect<io::GraphFile>(source, "g2o").name : from;
  Trajectory t;
  if (format_name == "matrix") {
    t = trajectoryFromSE2(deadReckonSE2(readMatrix3xN(source.stream(), source.name())));
  } else {
    io::ReadContext context;
    context.types = &reg.types;
    context.load.create_missing_vertices = true;
    const LoadedInput in = io::readGraph(source, reg.formats, context, format_name);
    if (in.format == "npz") {
      throw UsageError(input + ": a CMU homework file has no SE(2) odometry chain (point robot)");
    }
    // Created vertices keep their default estimates: the chain starts at the identity.
    if (in.created_vertices > 0) std::printf("%s\n", io::createdVerticesNote(in).c_str());
    t = init::deadReckonGraph(in.graph);
  }
  const std::size_t last = t.size() - 1;
  const Eigen::Isometry3d& p = t.pose(last);
  const double theta = std::atan2(p.linear()(1, 0), p.linear()(0, 0));
  std::printf(
      "%zu poses; last (pose %zu): x %.6f  y %.6f  theta %.6f rad (%.2f deg), %.4f m from the "
      "first\n",
      t.size(), last, p.translation().x(), p.translation().y(), theta, theta * kRadToDeg,
      (p.translation() - t.position(0)).norm());
  if (!output.empty()) {
    saveTrajectory(output, t, format, reg);
    std::printf("wrote %s\n", output.c_str());
  }
  return kExitOk;
}

// ---------------------------------------------------------------------------------------
// convert

namespace {
std::string joinNumbers(const std::vector<double>& values) {
  std::string out;
  for (double v : values) out += (out.empty() ? "" : " ") + support::formatDouble(v);
  return out;
}
}  // namespace

int cmdConvert(const std::vector<std::string>& args) {
  std::string input, output, format = "auto", from = "auto";
  std::vector<std::string> plugins;
  std::vector<double> info;
  po::options_description desc("options");
  desc.add_options()("help,h", "show this help")(
      "input", po::value(&input),
      "3xN relative-pose matrix file, a .g2o graph or a .npz homework file")(
      "output", po::value(&output),
      "OUT.g2o (from a matrix), or OUT.tum / OUT.kitti (from a .g2o)")(
      "no-loop-closure",
      "matrix input: the last column is odometry too, not a loop closure to pose 0")(
      "information", po::value(&info)->multitoken(),
      "matrix input: I11 I12 I13 I22 I23 I33 of every edge (default identity)")(
      "format", po::value(&format)->default_value("auto"), "trajectory output: auto, tum or kitti")(
      "from", po::value(&from)->default_value("auto"),
      "input format: auto (from its name and content), g2o, toro, isam, npz or matrix")(
      "plugin", po::value(&plugins)->composing(),
      "load types from this shared library (repeatable)");
  po::positional_options_description pos;
  pos.add("input", 1).add("output", 1);
  const auto vm = parse(args, desc, &pos);
  if (vm.count("help")) {
    printHelp(
        "usage: graphslam convert IN OUT [--from FORMAT] [--format tum|kitti] [--plugin LIB]...\n"
        "  .npz -> .g2o: a CMU 16-833 homework file as a point-robot graph (initial guess as "
        "estimates)\n"
        "  matrix -> .g2o: relative poses to an SE(2) pose graph (last column = loop closure to "
        "pose 0)\n"
        "  .g2o -> TUM/KITTI: the VERTEX_SE2 / VERTEX_SE3:QUAT estimates as a trajectory "
        "(timestamp = id)\n"
        "  TORO (VERTEX2/EDGE2, VERTEX3/EDGE3) or iSAM 2D -> .g2o: the graph in g2o's tags; "
        "vertices the file lacks are created and initialised",
        desc);
    return kExitOk;
  }
  if (input.empty() || output.empty()) throw UsageError("convert needs IN and OUT");
  Registries reg;
  loadRegistries(reg, plugins);
  checkGraphFormat(from, reg);
  InputOptions options;
  options.format = from;
  if (vm.count("no-loop-closure")) options.choices["loop-closure"] = "no";
  if (!info.empty()) options.choices["information"] = joinNumbers(info);
  LoadedInput in = loadInput(input, reg, options);
  std::printf("read %s: %s\n", in.path.c_str(), in.description.c_str());
  for (const auto& note : in.notes) std::printf("%s\n", note.c_str());
  const bool trajectory = format != "auto" || reg.formats.forOutput<Trajectory>(output) != nullptr;
  if (!trajectory && reg.formats.forOutput<io::GraphFile>(output) == nullptr) {
    throw UsageError("cannot tell the output format of '" + output +
                     "' from its name: end it in .g2o for a graph, or in .tum, .txt or .kitti "
                     "(or give --format tum|kitti) for its poses as a trajectory");
  }
  initializeCreatedVertices(in, in.graph, reg.solvers);
  if (trajectory) {
    const Trajectory t = io::trajectoryFromGraph(in.graph);
    saveTrajectory(output, t, format, reg);
    std::printf("wrote %s: %zu poses\n", output.c_str(), t.size());
    return kExitOk;
  }
  io::writeGraph(output, in.graph, reg.formats, {&reg.types});
  std::printf("wrote %s: %zu vertices, %zu edges\n", output.c_str(), in.graph.numVertices(),
              in.graph.numEdges());
  return kExitOk;
}

}  // namespace graphslam::apps
