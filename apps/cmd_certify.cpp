// SPDX-License-Identifier: MIT
// graphslam certify: SE-Sync's certificate of global optimality for a pose graph.
#include <cstdio>
#include <iostream>

#include "certify_cli.h"
#include "graphslam/io/g2o.h"
#include "graphslam/types_slam2d/edge_se2.h"
#include "graphslam/types_slam2d/vertex_se2.h"
#include "graphslam/types_slam3d/edges.h"
#include "graphslam/types_slam3d/vertex_se3.h"
#include "input.h"
#include "output_set.h"

namespace graphslam::apps {

namespace {

constexpr const char* kCertifyUsage =
    "usage: graphslam certify IN.g2o [-o OUT.g2o] [--start chordal|estimates] [--initial-rank N]\n"
    "                         [--max-rank N] [--information MODE] [--plugin LIB]...\n"
    "Certifies the global optimum of SE-Sync's objective for a 2D or 3D pose graph (Rosen et\n"
    "al., IJRR 2019): every EDGE_SE2 / EDGE_SE3:QUAT becomes kappa |R_j - R_i R~|_F^2 +\n"
    "tau |t_j - t_i - R_i t~|^2 with isotropic weights from its information matrix (not the\n"
    "full matrix: the file's chi2 is a different objective). The Riemannian staircase solves\n"
    "the rank-r relaxation, raises r along the certificate's negative eigenvector while the\n"
    "certificate S = Q - Lambda is not positive semidefinite, then rounds to rotations and\n"
    "recovers the translations. Prints 'certified globally optimal' with F(x), the dual bound,\n"
    "the relative suboptimality bound, lambda_min(S) and its residual, the rank and the times,\n"
    "or 'not certified' with the same numbers and why (exit 1, nothing written).\n"
    "Only pose graphs: landmarks, priors, other edge types, a disconnected graph, edges\n"
    "without rotation information and more than one fixed vertex are refused (exit 2).\n"
    "-o writes the certified poses (in the frame of the fixed vertex, else of the lowest id).";

/// The tag of a vertex or edge, for messages.
template <typename T>
std::string tagOf(const TypeRegistry& types, const T& x) {
  const std::string* tag = types.tagOf(x);
  return tag ? *tag : typeName(typeid(x));
}

bool isPose(const Vertex& v) {
  return dynamic_cast<const types_slam2d::VertexSE2*>(&v) ||
         dynamic_cast<const types_slam3d::VertexSE3*>(&v);
}

bool isRelativePose(const Edge& e) {
  return dynamic_cast<const types_slam2d::EdgeSE2*>(&e) ||
         dynamic_cast<const types_slam3d::EdgeSE3*>(&e);
}

certify::Options parseStart(const std::string& start, int initial_rank, int max_rank) {
  certify::Options options;
  options.start =
      parseChoice<certify::Options::Start>("start", start,
                                           {{"chordal", certify::Options::Start::kChordal},
                                            {"estimates", certify::Options::Start::kEstimates}});
  if (initial_rank < 2 || max_rank < initial_rank) {
    throw UsageError("--initial-rank must be at least 2 and --max-rank at least --initial-rank");
  }
  options.initial_rank = initial_rank;
  options.max_rank = max_rank;
  return options;
}

}  // namespace

void checkCertifiable(const Graph& graph, const TypeRegistry& types, const std::string& input) {
  for (const auto& [id, v] : graph.vertices()) {
    if (!isPose(*v)) {
      throw InputError(input + ": vertex " + std::to_string(id) + " is a " + tagOf(types, *v) +
                       "; certify supports pose graphs only (VERTEX_SE2 or VERTEX_SE3:QUAT): "
                       "landmarks and other vertices have no place in SE-Sync's relaxation");
    }
  }
  for (const auto& e : graph.edges()) {
    if (e->active() && !isRelativePose(*e)) {
      throw InputError(input + ": an edge " + tagOf(types, *e) + " (vertex " +
                       std::to_string(e->vertexId(0)) +
                       "); certify supports relative-pose edges only (EDGE_SE2 or "
                       "EDGE_SE3:QUAT): priors and landmark observations are not part of "
                       "SE-Sync's problem");
    }
  }
}

bool certifyBeforeOptimize(Graph& graph, const TypeRegistry& types, const std::string& input) {
  checkCertifiable(graph, types, input.empty() ? std::string("the graph") : input);
  const certify::CertificateReport report = certify::certify(graph, certify::Options{});
  std::cout << "certify: SE-Sync's objective (chordal rotation and translation terms with "
               "isotropic weights from the edges' information), not the file's chi2:\n"
            << report.report();
  std::cout << (report.certified
                    ? "certify: the poses are SE-Sync's certified optimum; refining the "
                      "optimizer's own objective from them\n"
                    : "certify: not certified; refining the optimizer's own objective from the "
                      "staircase's poses\n");
  return report.certified;
}

int cmdCertify(const std::vector<std::string>& args) {
  std::string input, output, start = "chordal", information = "refuse";
  int initial_rank = 5, max_rank = 10;
  std::vector<std::string> plugins;
  po::options_description desc("options");
  desc.add_options()("help,h", "show this help")("input", po::value(&input), "input pose graph")(
      "output,o", po::value(&output), "write the certified poses (.g2o)")(
      "start", po::value(&start)->default_value("chordal"),
      "chordal (SE-Sync's chordal relaxation of the rotations) or estimates (the file's own "
      "rotations; vertices the file does not define are placed by the global initialisation)")(
      "initial-rank", po::value(&initial_rank)->default_value(5),
      "first rank r of the relaxation over St(d, r)^n (at least 2; raised to d)")(
      "max-rank", po::value(&max_rank)->default_value(10),
      "highest rank the staircase climbs to before reporting 'not certified'")(
      "information", po::value(&information)->default_value("refuse"),
      "edges whose information is not positive definite: refuse, nearest-pd or isotropic")(
      "plugin", po::value(&plugins)->composing(), "load types from this shared library");
  po::positional_options_description pos;
  pos.add("input", 1);
  const auto vm = parse(args, desc, &pos);
  if (vm.count("help")) {
    printHelp(kCertifyUsage, desc);
    return kExitOk;
  }
  if (input.empty()) throw UsageError("certify needs an input file");
  const certify::Options options = parseStart(start, initial_rank, max_rank);
  OutputSet outputs({output}, {input});
  Registries reg;
  loadRegistries(reg, plugins);
  InputOptions input_options;
  input_options.information = parseInformationRepair(information);
  LoadedInput in = loadInput(input, reg, input_options);
  std::printf("%s: %s\n", input.c_str(), in.description.c_str());
  checkCertifiable(in.graph, reg.types, input);
  if (options.start == certify::Options::Start::kEstimates) {
    initializeCreatedVertices(in, in.graph, reg.solvers);
  }
  const certify::CertificateReport report = certify::certify(in.graph, options);
  std::cout << report.report();
  if (!report.certified) {
    if (!output.empty()) std::cout << "not writing " << output << "\n";
    outputs.abort();
    return kExitFailed;
  }
  return outputs.writeAll([&] {
    if (!output.empty()) {
      io::saveG2o(outputs.staged(output), in.graph, reg.types);
      std::cout << "wrote " << output << "\n";
    }
    outputs.commit();
    return kExitOk;
  });
}

}  // namespace graphslam::apps
