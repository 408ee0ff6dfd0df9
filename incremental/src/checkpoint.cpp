// SPDX-License-Identifier: MIT
// Checkpoints of IncrementalOptimizer (saveCheckpoint, loadCheckpoint).
//
// Format, version 1 (every number in the byte order of the machine that wrote it; a file
// of the other order is refused by its byte-order mark):
//   16 bytes  magic "GRAPHSLAM-CKPT\n" and a zero byte
//   u32       byte-order mark 0x01020304
//   u32       format version
//   u64       payload size in bytes
//   payload
//   u64       FNV-1a 64 checksum of the payload
// The payload: the options that decide the continuation (checked on loading), the update
// counter and gauge flag, the window (states with stamps, marginalised id ranges and
// count), the graph (parameters, vertices with estimates and fixed flags, edges in graph
// order with active flags; a marginalisation prior as its dimensions, Jacobian, offset and
// linearisation point) and the caller's note. Objects are named by registry tag.
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

#include "graphslam/incremental/checkpoint_bytes.h"
#include "graphslam/incremental/linear_prior_edge.h"
#include "graphslam/support/error.h"
#include "graphslam/support/file_util.h"
#include "optimizer_impl.h"

namespace graphslam::incremental {

namespace {

constexpr char kMagic[16] = "GRAPHSLAM-CKPT\n";
constexpr std::uint32_t kByteOrderMark = 0x01020304;
constexpr std::uint32_t kVersion = 1;
constexpr std::size_t kHeaderBytes = 16 + 4 + 4 + 8;
constexpr std::uint8_t kRegisteredEdge = 0;
constexpr std::uint8_t kPriorEdge = 1;

std::uint64_t fnv1a(const std::string& bytes) {
  std::uint64_t h = 14695981039346656037ull;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

std::string tagOrThrow(const std::string* tag, const std::string& what) {
  if (!tag) throw Error("saveCheckpoint: " + what + ": its type is not registered");
  return *tag;
}

// One byte: bit 0 reinitialize_landmarks, bit 1 keep_landmarks (files written before
// keep_landmarks existed hold 0 or 1, and read the same).
std::uint8_t landmarkPolicy(const WindowOptions& w) {
  return static_cast<std::uint8_t>((w.reinitialize_landmarks ? 1 : 0) | (w.keep_landmarks ? 2 : 0));
}

void writeOptions(ByteWriter& w, const Options& o) {
  w.put(o.relinearize_threshold);
  w.put<std::int64_t>(o.max_passes);
  w.put<std::int64_t>(o.relinearize_skip);
  w.put(o.backsubstitution_fraction);
  w.put<std::int64_t>(o.chain_min_front_rows);
  w.put<std::uint64_t>(o.window.states);
  w.put<std::uint64_t>(o.window.slack);
  w.put(o.window.seconds);
  w.put(o.window.rank_tolerance);
  w.put<std::uint8_t>(landmarkPolicy(o.window));
}

// Refuses a file written with other options than `o`, naming the first that differs.
void checkOptions(ByteReader& r, const Options& o) {
  const auto same = [&](const char* name, double saved, double now) {
    if (saved == now || (std::isnan(saved) && std::isnan(now))) return;
    std::ostringstream msg;
    msg << "it was written with " << name << " " << saved << ", this optimizer has " << now;
    r.fail(msg.str());
  };
  same("relinearize_threshold", r.get<double>(), o.relinearize_threshold);
  same("max_passes", static_cast<double>(r.get<std::int64_t>()), o.max_passes);
  same("relinearize_skip", static_cast<double>(r.get<std::int64_t>()), o.relinearize_skip);
  same("backsubstitution_fraction", r.get<double>(), o.backsubstitution_fraction);
  same("chain_min_front_rows", static_cast<double>(r.get<std::int64_t>()), o.chain_min_front_rows);
  same("window states", static_cast<double>(r.get<std::uint64_t>()),
       static_cast<double>(o.window.states));
  same("window slack", static_cast<double>(r.get<std::uint64_t>()),
       static_cast<double>(o.window.slack));
  same("window seconds", r.get<double>(), o.window.seconds);
  same("window rank_tolerance", r.get<double>(), o.window.rank_tolerance);
  same("window landmark policy (1: reinitialize_landmarks, 2: keep_landmarks)",
       r.get<std::uint8_t>(), landmarkPolicy(o.window));
}

void writeEdge(ByteWriter& w, const Edge& e, const TypeRegistry& types) {
  w.put<std::uint64_t>(e.numVertices());
  for (VertexId id : e.vertexIds()) w.put<std::int64_t>(id);
  w.put<std::uint8_t>(e.active() ? 1 : 0);
  if (const auto* prior = dynamic_cast<const LinearPriorEdge*>(&e)) {
    w.put(kPriorEdge);
    for (int d : prior->slotDimensions()) w.put<std::int64_t>(d);
    w.put<std::int64_t>(prior->priorJacobian().rows());
    w.putDoubles(prior->priorJacobian().data(),
                 static_cast<std::size_t>(prior->priorJacobian().size()));
    w.putDoubles(prior->priorOffset().data(),
                 static_cast<std::size_t>(prior->priorOffset().size()));
    w.putDoubles(prior->linearizationPoint());
    return;
  }
  const std::string what = "an edge on vertex " + std::to_string(e.vertexId(0));
  if (e.robustKernel()) {
    throw Error("saveCheckpoint: " + what +
                " has a robust kernel, which the checkpoint format does not hold yet");
  }
  w.put(kRegisteredEdge);
  w.putString(tagOrThrow(types.tagOf(e), what));
  w.put<std::uint64_t>(static_cast<std::uint64_t>(e.numParameters()));
  for (int k = 0; k < e.numParameters(); ++k)
    w.put<std::int64_t>(e.parameterId(static_cast<std::size_t>(k)));
  std::vector<double> data(static_cast<std::size_t>(e.measurementDataDimension()));
  e.getMeasurementData(data.data());
  w.putDoubles(data);
  data.assign(static_cast<std::size_t>(e.parameterDataDimension()), 0.0);
  e.getParameterData(data.data());
  w.putDoubles(data);
  w.putDoubles(e.informationData(), static_cast<std::size_t>(e.dimension()) * e.dimension());
}

std::unique_ptr<Edge> readEdge(ByteReader& r, const TypeRegistry& types, bool& active) {
  const auto n = r.get<std::uint64_t>();
  if (n > (1u << 20)) r.fail("an edge with " + std::to_string(n) + " vertices");
  std::vector<VertexId> ids(n);
  for (auto& id : ids) id = static_cast<VertexId>(r.get<std::int64_t>());
  active = r.get<std::uint8_t>() != 0;
  const auto kind = r.get<std::uint8_t>();
  if (kind == kPriorEdge) {
    std::vector<int> dims(n);
    int cols = 0;
    for (auto& d : dims) cols += d = static_cast<int>(r.get<std::int64_t>());
    const auto rows = r.get<std::int64_t>();
    const std::vector<double> j = r.getDoubles(static_cast<std::size_t>(rows * cols));
    const std::vector<double> off = r.getDoubles(static_cast<std::size_t>(rows));
    auto e = std::make_unique<LinearPriorEdge>(
        dims, Eigen::Map<const Eigen::MatrixXd>(j.data(), rows, cols),
        Eigen::Map<const Eigen::VectorXd>(off.data(), rows), r.getDoubles());
    e->setVertexIds(ids);
    return e;
  }
  if (kind != kRegisteredEdge) r.fail("an edge record of unknown kind " + std::to_string(kind));
  const std::string tag = r.getString();
  std::unique_ptr<Edge> e = types.createEdge(tag);
  if (!e) r.fail("edge type " + tag + " is not registered");
  e->setVertexIds(ids);
  const auto np = r.get<std::uint64_t>();
  if (np != static_cast<std::uint64_t>(e->numParameters()))
    r.fail(tag + ": wrong number of parameter ids");
  for (std::size_t k = 0; k < np; ++k)
    e->setParameterId(k, static_cast<ParameterId>(r.get<std::int64_t>()));
  e->setMeasurementData(
      r.getDoubles(static_cast<std::size_t>(e->measurementDataDimension())).data());
  e->setParameterData(r.getDoubles(static_cast<std::size_t>(e->parameterDataDimension())).data());
  e->setInformationData(
      r.getDoubles(static_cast<std::size_t>(e->dimension()) * e->dimension()).data());
  return e;
}

void writeGraph(ByteWriter& w, const Graph& g, const TypeRegistry& types) {
  w.put<std::uint64_t>(g.parameters().size());
  for (const auto& [id, p] : g.parameters()) {
    w.putString(tagOrThrow(types.tagOf(*p), "parameter " + std::to_string(id)));
    w.put<std::int64_t>(id);
    std::vector<double> data(static_cast<std::size_t>(p->dataDimension()));
    p->getData(data.data());
    w.putDoubles(data);
  }
  w.put<std::uint64_t>(g.numVertices());
  for (const auto& [id, v] : g.vertices()) {
    w.putString(tagOrThrow(types.tagOf(*v), "vertex " + std::to_string(id)));
    w.put<std::int64_t>(id);
    w.put<std::uint8_t>(v->fixed() ? 1 : 0);
    std::vector<double> data(static_cast<std::size_t>(v->estimateDataDimension()));
    v->getEstimateData(data.data());
    w.putDoubles(data);
    data.assign(static_cast<std::size_t>(v->parameterDataDimension()), 0.0);
    v->getParameterData(data.data());
    w.putDoubles(data);
  }
  w.put<std::uint64_t>(g.numEdges());
  for (const auto& e : g.edges()) writeEdge(w, *e, types);
}

Graph readGraph(ByteReader& r, const TypeRegistry& types) {
  Graph g;
  const auto np = r.get<std::uint64_t>();
  for (std::uint64_t k = 0; k < np; ++k) {
    const std::string tag = r.getString();
    auto p = types.createParameter(tag);
    if (!p) r.fail("parameter type " + tag + " is not registered");
    p->setId(static_cast<ParameterId>(r.get<std::int64_t>()));
    p->setData(r.getDoubles(static_cast<std::size_t>(p->dataDimension())).data());
    g.addParameter(std::move(p));
  }
  const auto nv = r.get<std::uint64_t>();
  for (std::uint64_t k = 0; k < nv; ++k) {
    const std::string tag = r.getString();
    auto v = types.createVertex(tag);
    if (!v) r.fail("vertex type " + tag + " is not registered");
    v->setId(static_cast<VertexId>(r.get<std::int64_t>()));
    v->setFixed(r.get<std::uint8_t>() != 0);
    v->setEstimateData(r.getDoubles(static_cast<std::size_t>(v->estimateDataDimension())).data());
    v->setParameterData(r.getDoubles(static_cast<std::size_t>(v->parameterDataDimension())).data());
    g.addVertex(std::move(v));
  }
  const auto ne = r.get<std::uint64_t>();
  for (std::uint64_t k = 0; k < ne; ++k) {
    bool active = true;
    Edge& e = g.addEdge(readEdge(r, types, active));
    if (!active) g.setEdgeActive(e, false);
  }
  return g;
}

}  // namespace

void IncrementalOptimizer::saveCheckpoint(const std::string& path, const TypeRegistry& types,
                                          const std::string& note) {
  Impl& m = *impl_;
  if (!m.new_edges.empty() || (!m.ready && m.built) ||
      (graph_.structureVersion() != m.version && !m.needs_rebuild)) {
    throw Error("saveCheckpoint: call update() after changing the graph first");
  }
  ByteWriter w;
  writeOptions(w, options_);
  w.put<std::int64_t>(m.update_count);
  w.put<std::uint8_t>(m.anchored ? 1 : 0);
  w.put<std::uint64_t>(m.states.size());
  for (const WindowState& s : m.states) {
    w.put<std::int64_t>(s.id);
    w.put(s.stamp);
  }
  w.put<std::uint64_t>(m.marginalized.size());
  for (const auto& [first, last] : m.marginalized) {
    w.put<std::int64_t>(first);
    w.put<std::int64_t>(last);
  }
  w.put<std::uint64_t>(m.marginalized_landmarks.size());
  for (VertexId id : m.marginalized_landmarks) w.put<std::int64_t>(id);
  w.put<std::uint64_t>(m.marginalized_count);
  writeGraph(w, graph_, types);
  w.putString(note);
  const std::string& payload = w.bytes();
  support::writeFileAtomically(path, [&](std::ostream& out) {
    out.write(kMagic, sizeof kMagic);
    const std::uint32_t head[2] = {kByteOrderMark, kVersion};
    out.write(reinterpret_cast<const char*>(head), sizeof head);
    const std::uint64_t size = payload.size();
    out.write(reinterpret_cast<const char*>(&size), sizeof size);
    out.write(payload.data(), static_cast<std::streamsize>(payload.size()));
    const std::uint64_t sum = fnv1a(payload);
    out.write(reinterpret_cast<const char*>(&sum), sizeof sum);
  });
  // The continuation starts from a factor eliminated afresh at the current estimates, as
  // it does after loadCheckpoint().
  m.needs_rebuild = true;
}

namespace {

// The payload of a checkpoint file, after checking its header, size and checksum.
std::string readPayload(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the checkpoint");
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto refuse = [&](const std::string& what) {
    throw InputError(path + ": checkpoint refused: " + what);
  };
  if (bytes.size() < 16 || std::memcmp(bytes.data(), kMagic, 16) != 0) {
    refuse("not a graphslam checkpoint (its first bytes are not \"GRAPHSLAM-CKPT\")");
  }
  if (bytes.size() < kHeaderBytes) refuse("truncated: it ends inside the header");
  std::uint32_t head[2];
  std::memcpy(head, bytes.data() + 16, sizeof head);
  if (head[0] != kByteOrderMark) refuse("written on a machine of the other byte order");
  if (head[1] != kVersion) {
    refuse("format version " + std::to_string(head[1]) + ", this build reads version " +
           std::to_string(kVersion));
  }
  std::uint64_t size = 0;
  std::memcpy(&size, bytes.data() + 24, sizeof size);
  const std::uint64_t have = bytes.size() - kHeaderBytes;
  if (have < size + 8) {
    refuse("truncated: " + std::to_string(bytes.size()) + " bytes, the header announces " +
           std::to_string(size + kHeaderBytes + 8));
  }
  if (have > size + 8) refuse("it has " + std::to_string(have - size - 8) + " bytes after its end");
  std::string payload = bytes.substr(kHeaderBytes, size);
  std::uint64_t sum = 0;
  std::memcpy(&sum, bytes.data() + kHeaderBytes + size, sizeof sum);
  if (sum != fnv1a(payload)) refuse("checksum mismatch: the file is corrupt");
  return payload;
}

}  // namespace

std::string IncrementalOptimizer::loadCheckpoint(const std::string& path,
                                                 const TypeRegistry& types) {
  if (graph_.numVertices() != 0 || graph_.numEdges() != 0 || !graph_.parameters().empty()) {
    throw Error("loadCheckpoint: the optimizer's graph must be empty");
  }
  const std::string payload = readPayload(path);
  ByteReader r(payload, path);
  checkOptions(r, options_);
  Impl fresh(graph_, options_);
  fresh.update_count = r.get<std::int64_t>();
  fresh.anchored = r.get<std::uint8_t>() != 0;
  const auto ns = r.get<std::uint64_t>();
  for (std::uint64_t k = 0; k < ns; ++k) {
    WindowState s;
    s.id = static_cast<VertexId>(r.get<std::int64_t>());
    s.stamp = r.get<double>();
    fresh.states.push_back(s);
    fresh.state_ids.insert(s.id);
  }
  const auto nm = r.get<std::uint64_t>();
  for (std::uint64_t k = 0; k < nm; ++k) {
    const auto first = static_cast<VertexId>(r.get<std::int64_t>());
    fresh.marginalized[first] = static_cast<VertexId>(r.get<std::int64_t>());
  }
  const auto nl = r.get<std::uint64_t>();
  for (std::uint64_t k = 0; k < nl; ++k) {
    fresh.marginalized_landmarks.insert(static_cast<VertexId>(r.get<std::int64_t>()));
  }
  fresh.marginalized_count = r.get<std::uint64_t>();
  Graph loaded;
  try {
    loaded = readGraph(r, types);
  } catch (const InputError&) {
    throw;
  } catch (const Error& e) {
    r.fail(e.what());
  }
  std::string note = r.getString();
  if (!r.done()) r.fail("its payload has bytes after the last record");
  for (const WindowState& s : fresh.states) {
    if (!loaded.hasVertex(s.id))
      r.fail("window state " + std::to_string(s.id) + " is not in its graph");
  }
  graph_ = std::move(loaded);
  impl_->update_count = fresh.update_count;
  impl_->anchored = fresh.anchored;
  impl_->states = std::move(fresh.states);
  impl_->state_ids = std::move(fresh.state_ids);
  impl_->marginalized = std::move(fresh.marginalized);
  impl_->marginalized_landmarks = std::move(fresh.marginalized_landmarks);
  impl_->marginalized_count = fresh.marginalized_count;
  impl_->needs_rebuild = true;
  impl_->built = true;
  impl_->ready = true;
  impl_->version = graph_.structureVersion();
  impl_->new_edges.clear();
  return note;
}

}  // namespace graphslam::incremental
