// SPDX-License-Identifier: MIT
#include "hessian_structure.h"

#include <algorithm>
#include <numeric>
#include <unordered_map>

#include "graphslam/core/block_pattern.h"
#include "graphslam/core/linear_system.h"

namespace graphslam::detail {

bool HessianStructure::stale(const Graph& graph) const {
  if (graph.structureVersion() != version_) return true;
  std::size_t i = 0;
  for (const auto& [id, v] : graph.vertices()) {
    if (fixed_snapshot_[i++] != static_cast<char>(v->fixed())) return true;
  }
  return false;
}

void HessianStructure::build(Graph& graph) {
  version_ = graph.structureVersion();
  // Every array gets its exact size up front: on large graphs (1M vertices) doubling
  // growth would leave up to half of each one unused.
  fixed_snapshot_.clear();
  fixed_snapshot_.reserve(graph.numVertices());
  active_vertices_.clear();
  active_vertices_.reserve(graph.numVertices());
  block_starts_.assign(1, 0);
  block_starts_.reserve(graph.numVertices() + 1);
  int col = 0;
  for (const auto& [id, v] : graph.vertices()) {
    fixed_snapshot_.push_back(static_cast<char>(v->fixed()));
    v->setHessianIndex(-1);
    if (v->fixed() || v->edges().empty()) continue;
    v->setHessianIndex(col);
    active_vertices_.push_back(v.get());
    col += v->dimension();
    block_starts_.push_back(col);
  }
  n_ = col;
  const int nb = static_cast<int>(active_vertices_.size());
  // Block of a vertex, through the column index just assigned (no hashing).
  std::vector<int> block_of_col(static_cast<std::size_t>(n_), -1);
  for (int b = 0; b < nb; ++b) block_of_col[block_starts_[b]] = b;
  auto block_of = [&](const Vertex* v) {
    return v->hessianIndex() >= 0 ? block_of_col[v->hessianIndex()] : -1;
  };

  // Block pattern: for every block column, the block rows (<= column) it holds.
  active_edges_.clear();
  active_edges_.reserve(graph.edges().size());
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(graph.edges().size());
  std::vector<int> blocks;
  for (const auto& e : graph.edges()) {
    blocks.clear();
    for (std::size_t s = 0; s < e->numVertices(); ++s) blocks.push_back(block_of(e->vertex(s)));
    if (std::all_of(blocks.begin(), blocks.end(), [](int b) { return b < 0; })) continue;
    active_edges_.push_back(e.get());
    for (std::size_t a = 0; a < blocks.size(); ++a) {
      for (std::size_t b = a + 1; b < blocks.size(); ++b) {
        if (blocks[a] >= 0 && blocks[b] >= 0) pairs.emplace_back(blocks[a], blocks[b]);
      }
    }
  }
  const BlockPattern pattern = BlockPattern::fromPairs(nb, pairs);

  // Scalar CSC: every column of block column j holds all rows of its row blocks, so the
  // diagonal block is stored full and every column of a block has the same length.
  // within[k]: offset of the k-th row block of its column within the column.
  std::vector<int> within(pattern.rows.size());
  std::vector<int> col_len(static_cast<std::size_t>(nb));
  std::size_t nnz = 0;
  for (int j = 0; j < nb; ++j) {
    int len = 0;
    for (int k = pattern.ptr[j]; k < pattern.ptr[j + 1]; ++k) {
      within[k] = len;
      const int r = pattern.rows[k];
      len += block_starts_[r + 1] - block_starts_[r];
    }
    col_len[j] = len;
    nnz += static_cast<std::size_t>(len) *
           static_cast<std::size_t>(block_starts_[j + 1] - block_starts_[j]);
  }
  col_ptr_.assign(static_cast<std::size_t>(n_) + 1, 0);
  row_idx_.clear();
  row_idx_.reserve(nnz);
  diag_pos_.assign(static_cast<std::size_t>(n_), 0);
  for (int j = 0; j < nb; ++j) {
    const int dj = block_starts_[j + 1] - block_starts_[j];
    const int diag_at = pattern.find(j, j);
    for (int k = 0; k < dj; ++k) {
      const int c = block_starts_[j] + k;
      col_ptr_[c + 1] = col_ptr_[c] + col_len[j];
      for (int q = pattern.ptr[j]; q < pattern.ptr[j + 1]; ++q) {
        const int r = pattern.rows[q];
        for (int i = block_starts_[r]; i < block_starts_[r + 1]; ++i) row_idx_.push_back(i);
      }
      diag_pos_[c] = col_ptr_[c] + within[diag_at] + k;
    }
  }

  auto block_ref = [&](int bi, int bj) {
    HessianBlockRef ref;
    ref.transposed = bi > bj;
    if (ref.transposed) std::swap(bi, bj);
    ref.offset = col_ptr_[block_starts_[bj]] + within[pattern.find(bi, bj)];
    ref.stride = col_len[bj];
    return ref;
  };

  refs_.clear();
  b_offsets_.clear();
  slot_blocks_.clear();
  edge_ref_start_.clear();
  edge_b_start_.clear();
  std::size_t num_slots = 0, num_refs = 0;
  for (const Edge* e : active_edges_) {
    num_slots += e->numVertices();
    num_refs += e->numVertices() * (e->numVertices() + 1) / 2;
  }
  refs_.reserve(num_refs);
  b_offsets_.reserve(num_slots);
  slot_blocks_.reserve(num_slots);
  edge_ref_start_.reserve(active_edges_.size());
  edge_b_start_.reserve(active_edges_.size());
  for (Edge* e : active_edges_) {
    edge_ref_start_.push_back(refs_.size());
    edge_b_start_.push_back(b_offsets_.size());
    const std::size_t n = e->numVertices();
    for (std::size_t a = 0; a < n; ++a) {
      const Vertex* va = e->vertex(a);
      b_offsets_.push_back(va->hessianIndex());
      slot_blocks_.push_back(block_of(va));
      for (std::size_t b = a; b < n; ++b) {
        const Vertex* vb = e->vertex(b);
        if (va->hessianIndex() < 0 || vb->hessianIndex() < 0) {
          refs_.push_back(HessianBlockRef{});
        } else {
          refs_.push_back(block_ref(block_of(va), block_of(vb)));
        }
      }
    }
  }
}

SparseStructure HessianStructure::sparseStructure() const {
  SparseStructure s;
  s.n = n_;
  s.col_ptr = col_ptr_.data();
  s.row_idx = row_idx_.data();
  s.block_starts = block_starts_.data();
  s.num_blocks = static_cast<int>(active_vertices_.size());
  return s;
}

void HessianStructure::assemble(std::vector<double>& values, std::vector<double>& gradient) const {
  values.assign(row_idx_.size(), 0.0);
  gradient.assign(static_cast<std::size_t>(n_), 0.0);
  QuadraticFormTarget target;
  target.hessian = values.data();
  target.gradient = gradient.data();
  for (std::size_t k = 0; k < active_edges_.size(); ++k) {
    target.blocks = refs_.data() + edge_ref_start_[k];
    target.b_offsets = b_offsets_.data() + edge_b_start_[k];
    active_edges_[k]->constructQuadraticForm(target);
  }
}

VertexId HessianStructure::vertexOfColumn(int col) const {
  if (col < 0 || col >= n_) return -1;
  const auto it = std::upper_bound(block_starts_.begin(), block_starts_.end(), col);
  const auto block = (it - block_starts_.begin()) - 1;
  return active_vertices_[static_cast<std::size_t>(block)]->id();
}

namespace {
struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};
}  // namespace

std::vector<std::vector<VertexId>> HessianStructure::unanchoredGroups(std::size_t max_ids) const {
  // Components of free vertices touched by a unary edge or an edge to a fixed vertex are
  // determined; the others float.
  const auto& active = active_vertices_;
  UnionFind uf(active.size());
  std::vector<char> anchored(active.size(), 0);
  std::vector<int> slots;
  for (std::size_t k = 0; k < active_edges_.size(); ++k) {
    const Edge* e = active_edges_[k];
    slots.clear();
    // The blocks recorded at build (not hessianIndex(): another structure on the same
    // graph may have set it since).
    for (std::size_t s = 0; s < e->numVertices(); ++s) {
      const int b = slot_blocks_[edge_b_start_[k] + s];
      if (b >= 0) slots.push_back(b);
    }
    for (std::size_t j = 1; j < slots.size(); ++j) uf.unite(slots[0], slots[j]);
    if (slots.size() < e->numVertices() || e->numVertices() == 1) anchored[slots[0]] = 1;
  }
  std::vector<char> root_anchored(active.size(), 0);
  for (std::size_t i = 0; i < active.size(); ++i) {
    if (anchored[i]) root_anchored[uf.find(static_cast<int>(i))] = 1;
  }
  std::vector<std::vector<VertexId>> groups;
  std::vector<int> group_of_root(active.size(), -1);
  for (std::size_t i = 0; i < active.size(); ++i) {
    const int root = uf.find(static_cast<int>(i));
    if (root_anchored[root]) continue;
    if (group_of_root[root] < 0) {
      group_of_root[root] = static_cast<int>(groups.size());
      groups.emplace_back();
    }
    auto& group = groups[group_of_root[root]];
    if (group.size() < max_ids) group.push_back(active[i]->id());
  }
  return groups;
}

GaugeFix::GaugeFix(Graph& graph, bool enabled) {
  if (!enabled) return;
  if (Vertex* v = fixGaugeIfFree(graph)) {
    vertices_.push_back(v);
    ids_.push_back(v->id());
  }
}

GaugeFix::~GaugeFix() {
  for (Vertex* v : vertices_) v->setFixed(false);
}

}  // namespace graphslam::detail
