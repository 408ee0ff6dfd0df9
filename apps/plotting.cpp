// SPDX-License-Identifier: MIT
#include "plotting.h"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <set>

#include "graphslam/support/error.h"
#include "graphslam/support/file_util.h"
#include "graphslam/types_slam2d/vertex_se2.h"

namespace graphslam::apps {

namespace {

/// Runs argv without a shell; returns the exit status (-1 if it could not start). `quiet`:
/// no output; `stderr_fd` >= 0: the child's error output goes there.
int run(const std::vector<std::string>& argv, bool quiet, int stderr_fd = -1) {
  std::fflush(nullptr);  // the child must not inherit (and re-emit) buffered output
  const pid_t pid = ::fork();
  if (pid < 0) return -1;
  if (pid == 0) {
    if (quiet) {
      std::freopen("/dev/null", "w", stdout);
      std::freopen("/dev/null", "w", stderr);
    }
    if (stderr_fd >= 0) ::dup2(stderr_fd, 2);
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));  // execvp's API
    args.push_back(nullptr);
    ::execvp(args[0], args.data());
    ::_exit(127);
  }
  int status = 0;
  if (::waitpid(pid, &status, 0) < 0) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string plotDir() {
  if (const char* env = std::getenv("GRAPHSLAM_PLOT_DIR"); env && *env) return env;
  return GRAPHSLAM_PLOT_DIR;
}

}  // namespace

int runCommand(const std::vector<std::string>& argv, bool quiet) { return run(argv, quiet); }

std::string findPlotPython() {
  std::vector<std::string> candidates;
  if (const char* env = std::getenv("GRAPHSLAM_PYTHON"); env && *env) candidates.emplace_back(env);
  candidates.emplace_back("/usr/bin/python3");
  candidates.emplace_back("python3");
  for (const auto& py : candidates) {
    if (run({py, "-c", "import matplotlib"}, true) == 0) return py;
  }
  return {};
}

void runPlotScript(const std::string& script, const std::vector<std::string>& args) {
  const std::string python = findPlotPython();
  if (python.empty()) {
    throw Error(
        "plotting needs Python 3 with matplotlib, and none was found (tried $GRAPHSLAM_PYTHON, "
        "/usr/bin/python3, python3): install it with 'apt-get install python3-matplotlib'");
  }
  std::vector<std::string> argv{python, plotDir() + "/" + script};
  argv.insert(argv.end(), args.begin(), args.end());
  // The script's error output is kept aside: a failure is reported by its last line (the
  // exception), never as a Python traceback.
  char name[] = "/tmp/graphslam-plot-XXXXXX";
  const int fd = ::mkstemp(name);
  const int rc = run(argv, false, fd);
  std::string last;
  if (fd >= 0) {
    ::close(fd);
    std::ifstream err(name);
    for (std::string line; std::getline(err, line);) {
      if (line.find_first_not_of(" \t") != std::string::npos) last = line;
    }
    std::remove(name);
  }
  if (rc != 0) {
    throw Error("plot script " + script + " failed (exit " + std::to_string(rc) + ")" +
                (last.empty() ? std::string() : ": " + last));
  }
}

/// Positions of the vertices that have one (see eval::vertexPosition), by id.
std::map<VertexId, Eigen::Vector2d> positions(const Graph& graph) {
  std::map<VertexId, Eigen::Vector2d> out;
  for (const auto& [id, v] : graph.vertices()) {
    Eigen::Vector2d p;
    if (eval::vertexPosition(*v, p)) out.emplace(id, p);
  }
  return out;
}

void printErrors(const char* what, const eval::PositionErrorStats& before,
                 const eval::PositionErrorStats& after) {
  if (!after.count) return;
  std::printf(
      "  %-10s %5zu   rmse %.6f  mean %.6f  max %.6f   ->   rmse %.6f  mean %.6f  max %.6f\n", what,
      after.count, before.rmse, before.mean, before.max, after.rmse, after.mean, after.max);
}

/// Writes the before/after/ground-truth positions as CSV and draws them (plot_points.py).
/// Poses are the ground truth's pose ids, or else the VERTEX_SE2 vertices.
void plotPoints(const std::string& png, const std::string& title, const Graph& graph,
                const std::map<VertexId, Eigen::Vector2d>& initial,
                const io::PointGroundTruth& truth, const std::string& shown,
                const std::string& panels) {
  std::set<VertexId> pose_ids(truth.pose_ids.begin(), truth.pose_ids.end());
  if (truth.empty()) {
    for (const auto& [id, v] : graph.vertices()) {
      if (dynamic_cast<const types_slam2d::VertexSE2*>(v.get())) pose_ids.insert(id);
    }
  }
  const std::string data = png + ".points.csv";
  support::writeFileAtomically(data, [&](std::ostream& out) {
    out.precision(17);
    out << "set,role,id,x,y\n";
    auto write = [&](const char* set, const std::map<VertexId, Eigen::Vector2d>& points) {
      for (const auto& [id, p] : points) {
        out << set << ',' << (pose_ids.count(id) ? "pose" : "landmark") << ',' << id << ',' << p.x()
            << ',' << p.y() << '\n';
      }
    };
    write("initial", initial);
    write("final", positions(graph));
    std::map<VertexId, Eigen::Vector2d> gt;
    for (std::size_t k = 0; k < truth.pose_ids.size(); ++k) gt[truth.pose_ids[k]] = truth.poses[k];
    for (std::size_t k = 0; k < truth.landmark_ids.size(); ++k) {
      gt[truth.landmark_ids[k]] = truth.landmarks[k];
    }
    write("truth", gt);
  });
  const TemporaryFile remove_data{data};
  runPlotScript("plot_points.py", {data, png, title, panels});
  std::printf("wrote %s\n", (shown.empty() ? png : shown).c_str());
}

}  // namespace graphslam::apps
