// SPDX-License-Identifier: MIT
#include "hessian_structure.h"

#include <algorithm>
#include <numeric>
#include <unordered_map>

#include "graphslam/optimizer/linear_system.h"
#include "graphslam/support/block_pattern.h"

namespace graphslam::detail {

namespace {
/// The lower-triangle pattern of the symmetric matrix whose upper one is `upper`: the
/// transpose, rows sorted in every column.
support::BlockPattern transposed(const support::BlockPattern& upper) {
  const int nb = upper.numBlocks();
  support::BlockPattern lower;
  lower.ptr.assign(static_cast<std::size_t>(nb) + 1, 0);
  for (int r : upper.rows) ++lower.ptr[static_cast<std::size_t>(r) + 1];
  for (int c = 0; c < nb; ++c) lower.ptr[c + 1] += lower.ptr[c];
  lower.rows.resize(upper.rows.size());
  std::vector<int> next(lower.ptr.begin(), lower.ptr.end() - 1);
  for (int c = 0; c < nb; ++c) {  // columns in increasing order: rows come sorted
    for (int k = upper.ptr[c]; k < upper.ptr[c + 1]; ++k) lower.rows[next[upper.rows[k]]++] = c;
  }
  return lower;
}
}  // namespace

bool HessianStructure::stale(const Graph& graph) const {
  if (graph.structureVersion() != version_) return true;
  std::size_t i = 0;
  for (const auto& [id, v] : graph.vertices()) {
    if (fixed_snapshot_[i++] != static_cast<char>(v->fixed())) return true;
  }
  return false;
}

void HessianStructure::build(Graph& graph, const std::vector<int>* block_order) {
  version_ = graph.structureVersion();
  assignColumns(graph, block_order);
  std::vector<std::pair<int, int>> pairs;
  std::vector<int> first_block;
  collectEdges(graph, pairs, first_block);
  if (lower_) sortEdgesByFirstBlock(first_block);
  // Exact sizes (large graphs), copied only when the room reserved was not all used.
  if (b_offsets_.capacity() != b_offsets_.size()) std::vector<int>(b_offsets_).swap(b_offsets_);
  if (edge_b_start_.capacity() != edge_b_start_.size()) {
    std::vector<std::uint32_t>(edge_b_start_).swap(edge_b_start_);
  }
  const int nb = static_cast<int>(active_vertices_.size());
  const support::BlockPattern pattern =
      lower_ ? transposed(support::BlockPattern::fromPairs(nb, pairs))
             : support::BlockPattern::fromPairs(nb, pairs);
  buildScalarPattern(pattern);
  support::LargeVector<HessianBlockRef>().swap(refs_);
  std::vector<std::uint32_t>().swap(edge_ref_start_);
}

void HessianStructure::assignColumns(Graph& graph, const std::vector<int>* block_order) {
  // Every array gets its exact size up front: on large graphs doubling growth would leave
  // up to half of each one unused.
  fixed_snapshot_.clear();
  fixed_snapshot_.reserve(graph.numVertices());
  active_vertices_.clear();
  active_vertices_.reserve(graph.numVertices());
  for (const auto& [id, v] : graph.vertices()) {
    fixed_snapshot_.push_back(static_cast<char>(v->fixed()));
    v->build_block_ = -1;
    if (v->fixed() || std::none_of(v->edges().begin(), v->edges().end(),
                                   [](const Edge* e) { return e->active(); })) {
      continue;
    }
    active_vertices_.push_back(v.get());
  }
  lower_ = block_order != nullptr;
  if (lower_) {
    std::vector<Vertex*> by_id;
    by_id.swap(active_vertices_);
    active_vertices_.reserve(by_id.size());
    for (int b : *block_order) active_vertices_.push_back(by_id[static_cast<std::size_t>(b)]);
  }
  block_starts_.assign(1, 0);
  block_starts_.reserve(active_vertices_.size() + 1);
  int col = 0;
  for (std::size_t b = 0; b < active_vertices_.size(); ++b) {
    Vertex* v = active_vertices_[b];
    v->build_block_ = static_cast<int>(b);
    col += v->dimension();
    block_starts_.push_back(col);
  }
  n_ = col;
}

void HessianStructure::collectEdges(const Graph& graph, std::vector<std::pair<int, int>>& pairs,
                                    std::vector<int>& first_block) {
  const int nb = static_cast<int>(active_vertices_.size());
  // Block of a vertex, through the scratch index assignColumns just set (no hashing).
  auto block_of = [](const Vertex* v) { return v->build_block_; };
  active_edges_.clear();
  active_edges_.reserve(graph.edges().size());
  pairs.reserve(graph.edges().size());
  std::vector<int> blocks;
  // In a solver's order, the edges go by their first block in that order (a counting
  // sort): assembling H then writes its columns in turn instead of all over the array.
  if (lower_) first_block.reserve(graph.edges().size());
  // Every active edge's slots: their columns (b's offsets, -1 for a fixed vertex),
  // recorded now, while the vertices are visited anyway (the scratch index is this
  // build's only). The block positions follow at the first
  // assembly (buildRefs): a structure rebuilt in a solver's order before any assembly
  // never computes them twice.
  // Room for binary edges (the usual kind; others make the arrays grow).
  b_offsets_.clear();
  b_offsets_.reserve(2 * graph.edges().size());
  edge_b_start_.clear();
  edge_b_start_.reserve(graph.edges().size() + 1);
  for (const auto& e : graph.edges()) {
    if (!e->active()) continue;
    blocks.clear();
    for (std::size_t s = 0; s < e->numVertices(); ++s) blocks.push_back(block_of(e->vertex(s)));
    int first = nb;
    for (int b : blocks) first = b >= 0 ? std::min(first, b) : first;
    if (first == nb) continue;
    active_edges_.push_back(e.get());
    edge_b_start_.push_back(static_cast<std::uint32_t>(b_offsets_.size()));
    for (int b : blocks) b_offsets_.push_back(b >= 0 ? block_starts_[b] : -1);
    if (lower_) first_block.push_back(first);
    for (std::size_t a = 0; a < blocks.size(); ++a) {
      for (std::size_t b = a + 1; b < blocks.size(); ++b) {
        if (blocks[a] >= 0 && blocks[b] >= 0) pairs.emplace_back(blocks[a], blocks[b]);
      }
    }
  }
  edge_b_start_.push_back(static_cast<std::uint32_t>(b_offsets_.size()));
}

void HessianStructure::sortEdgesByFirstBlock(const std::vector<int>& first_block) {
  const int nb = static_cast<int>(active_vertices_.size());
  const std::size_t m = active_edges_.size();
  std::vector<std::size_t> start(static_cast<std::size_t>(nb) + 1, 0);
  for (int b : first_block) ++start[static_cast<std::size_t>(b) + 1];
  for (int b = 0; b < nb; ++b) start[b + 1] += start[b];
  std::vector<std::size_t> position(m);  // of every edge in the sorted order
  std::vector<Edge*> sorted(m);
  std::vector<std::uint32_t> sorted_start(m + 1, 0);
  for (std::size_t k = 0; k < m; ++k) {
    position[k] = start[static_cast<std::size_t>(first_block[k])]++;
    sorted[position[k]] = active_edges_[k];
    sorted_start[position[k] + 1] = edge_b_start_[k + 1] - edge_b_start_[k];
  }
  for (std::size_t k = 0; k < m; ++k) sorted_start[k + 1] += sorted_start[k];
  std::vector<int> sorted_offsets(b_offsets_.size());
  for (std::size_t k = 0; k < m; ++k) {
    std::copy(b_offsets_.begin() + edge_b_start_[k], b_offsets_.begin() + edge_b_start_[k + 1],
              sorted_offsets.begin() + sorted_start[position[k]]);
  }
  active_edges_.swap(sorted);
  b_offsets_.swap(sorted_offsets);
  edge_b_start_.swap(sorted_start);
}

void HessianStructure::buildScalarPattern(const support::BlockPattern& pattern) {
  const int nb = static_cast<int>(active_vertices_.size());
  // Scalar CSC: every column of block column j holds all rows of its row blocks (those
  // <= j, or >= j for the lower triangle), so the diagonal block is stored full and every
  // column of a block has the same length. within[k]: offset of the k-th row block of its
  // column within the column.
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
  row_idx_.resize(nnz);
  diag_pos_.assign(static_cast<std::size_t>(n_), 0);
  int* out = row_idx_.data();
  for (int j = 0; j < nb; ++j) {
    const int dj = block_starts_[j + 1] - block_starts_[j];
    // The diagonal block closes an upper column (rows <= j, sorted) and opens a lower one.
    const int diag_at = lower_ ? pattern.ptr[j] : pattern.ptr[j + 1] - 1;
    // The first column's rows, then the same rows for the block's other columns.
    const int* first = out;
    for (int q = pattern.ptr[j]; q < pattern.ptr[j + 1]; ++q) {
      const int r = pattern.rows[q];
      for (int i = block_starts_[r]; i < block_starts_[r + 1]; ++i) *out++ = i;
    }
    for (int k = 0; k < dj; ++k) {
      const int c = block_starts_[j] + k;
      col_ptr_[c + 1] = col_ptr_[c] + col_len[j];
      if (k > 0) out = std::copy(first, first + col_len[j], out);
      diag_pos_[c] = col_ptr_[c] + within[diag_at] + k;
    }
  }
}

std::vector<int> HessianStructure::blockOfColumn() const {
  std::vector<int> block(static_cast<std::size_t>(n_));
  for (std::size_t b = 0; b + 1 < block_starts_.size(); ++b) {
    std::fill(block.begin() + block_starts_[b], block.begin() + block_starts_[b + 1],
              static_cast<int>(b));
  }
  return block;
}

void HessianStructure::buildRefs() {
  const std::vector<int> block = blockOfColumn();
  // Block (bi, bj) is stored as (row, column) in the stored triangle, transposed when that
  // is (bj, bi); found by its first row in the column's sorted rows.
  auto block_ref = [&](int bi, int bj) {
    HessianBlockRef ref;
    if (bi == bj) {  // a diagonal block: where diagonalPositions() says, no search
      const int c = block_starts_[bi];
      ref.offset = diag_pos_[c];
      ref.stride = col_ptr_[c + 1] - col_ptr_[c];
      return ref;
    }
    const int row = lower_ ? std::max(bi, bj) : std::min(bi, bj);
    const int column = lower_ ? std::min(bi, bj) : std::max(bi, bj);
    ref.transposed = row != bi;
    const int c = block_starts_[column];
    const int* first = row_idx_.data() + col_ptr_[c];
    const int* last = row_idx_.data() + col_ptr_[c + 1];
    ref.offset =
        col_ptr_[c] + static_cast<int>(std::lower_bound(first, last, block_starts_[row]) - first);
    ref.stride = col_ptr_[c + 1] - col_ptr_[c];
    return ref;
  };
  // Slot counts from the structure's own arrays: the edges themselves are not visited.
  std::size_t num_refs = 0;
  for (std::size_t k = 0; k < active_edges_.size(); ++k) {
    const std::size_t n = edge_b_start_[k + 1] - edge_b_start_[k];
    num_refs += n * (n + 1) / 2;
  }
  refs_.clear();
  refs_.reserve(num_refs);
  edge_ref_start_.clear();
  edge_ref_start_.reserve(active_edges_.size());
  for (std::size_t k = 0; k < active_edges_.size(); ++k) {
    edge_ref_start_.push_back(static_cast<std::uint32_t>(refs_.size()));
    const int* cols = b_offsets_.data() + edge_b_start_[k];
    const std::size_t n = edge_b_start_[k + 1] - edge_b_start_[k];
    for (std::size_t a = 0; a < n; ++a) {
      for (std::size_t b = a; b < n; ++b) {
        if (cols[a] < 0 || cols[b] < 0) {
          refs_.push_back(HessianBlockRef{});
        } else {
          refs_.push_back(block_ref(block[cols[a]], block[cols[b]]));
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
  s.lower = lower_;
  return s;
}

void HessianStructure::assemble(support::LargeVector<double>& values,
                                std::vector<double>& gradient) {
  if (edge_ref_start_.size() != active_edges_.size()) buildRefs();
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
  const std::vector<int> block = blockOfColumn();
  std::vector<int> slots;
  for (std::size_t k = 0; k < active_edges_.size(); ++k) {
    slots.clear();
    // The columns recorded at build; the edges themselves are not visited.
    const std::size_t n = edge_b_start_[k + 1] - edge_b_start_[k];
    for (std::size_t s = 0; s < n; ++s) {
      const int col = b_offsets_[edge_b_start_[k] + s];
      if (col >= 0) slots.push_back(block[col]);
    }
    for (std::size_t j = 1; j < slots.size(); ++j) uf.unite(slots[0], slots[j]);
    if (slots.size() < n || n == 1) anchored[slots[0]] = 1;
  }
  std::vector<char> root_anchored(active.size(), 0);
  for (std::size_t i = 0; i < active.size(); ++i) {
    if (anchored[i]) root_anchored[uf.find(static_cast<int>(i))] = 1;
  }
  std::vector<std::vector<VertexId>> groups;
  std::vector<const Vertex*> anchor;  // per group: the lowest id of the largest dimension
  std::vector<int> group_of_root(active.size(), -1);
  for (std::size_t i = 0; i < active.size(); ++i) {
    const int root = uf.find(static_cast<int>(i));
    if (root_anchored[root]) continue;
    if (group_of_root[root] < 0) {
      group_of_root[root] = static_cast<int>(groups.size());
      groups.emplace_back();
      anchor.push_back(active[i]);
    }
    const auto g = static_cast<std::size_t>(group_of_root[root]);
    if (groups[g].size() < max_ids) groups[g].push_back(active[i]->id());
    if (betterGaugeAnchor(*active[i], anchor[g])) anchor[g] = active[i];
  }
  for (std::size_t g = 0; g < groups.size(); ++g) {  // the anchor first
    auto& ids = groups[g];
    const VertexId a = anchor[g]->id();
    if (ids.front() == a) continue;
    const auto it = std::find(ids.begin(), ids.end(), a);
    if (it != ids.end()) {
      ids.erase(it);
    } else if (ids.size() == max_ids) {
      ids.pop_back();
    }
    ids.insert(ids.begin(), a);
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

void GaugeFix::anchorGroups(Graph& graph, const std::vector<std::vector<VertexId>>& groups) {
  for (const auto& group : groups) {
    Vertex* v = group.empty() ? nullptr : graph.vertex(group.front());
    if (!v || v->fixed()) continue;
    v->setFixed(true);
    vertices_.push_back(v);
    ids_.push_back(v->id());
  }
}

GaugeFix::~GaugeFix() {
  for (Vertex* v : vertices_) v->setFixed(false);
}

}  // namespace graphslam::detail
