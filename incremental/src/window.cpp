// SPDX-License-Identifier: MIT
// Fixed-lag smoothing of IncrementalOptimizer: the window's states, which of them leave
// after an update, and their marginalisation (linear_prior_edge.h).
#include <algorithm>
#include <cmath>
#include <memory>
#include <set>

#include "graphslam/incremental/linear_prior_edge.h"
#include "graphslam/support/error.h"
#include "optimizer_impl.h"

namespace graphslam::incremental {

void IncrementalOptimizer::addState(VertexId id, double stamp) {
  if (!graph_.hasVertex(id)) {
    throw Error("addState: vertex " + std::to_string(id) + " is not in the graph");
  }
  if (impl_->state_ids.count(id)) {
    throw Error("addState: vertex " + std::to_string(id) + " is a state already");
  }
  if (!impl_->states.empty() && std::isfinite(stamp) && std::isfinite(impl_->states.back().stamp) &&
      stamp < impl_->states.back().stamp) {
    throw Error("addState: vertex " + std::to_string(id) + "'s stamp " + std::to_string(stamp) +
                " is older than the newest state's (" + std::to_string(impl_->states.back().stamp) +
                ")");
  }
  impl_->states.push_back(WindowState{id, stamp});
  impl_->state_ids.insert(id);
}

std::vector<VertexId> IncrementalOptimizer::marginalize(const std::vector<VertexId>& states) {
  for (VertexId id : states) {
    if (!impl_->state_ids.count(id)) {
      throw Error("marginalize: vertex " + std::to_string(id) + " is not a state of the window");
    }
  }
  return impl_->marginalizeStates(states);
}

void IncrementalOptimizer::restart() {
  auto fresh = std::make_unique<Impl>(graph_, options_);
  fresh->factor.setChainMinFrontRows(options_.chain_min_front_rows);
  fresh->version = graph_.structureVersion();
  fresh->states = std::move(impl_->states);
  fresh->state_ids = std::move(impl_->state_ids);
  fresh->marginalized = std::move(impl_->marginalized);
  fresh->marginalized_landmarks = std::move(impl_->marginalized_landmarks);
  fresh->marginalized_count = impl_->marginalized_count;
  impl_ = std::move(fresh);
}

bool IncrementalOptimizer::isMarginalized(VertexId id) const { return impl_->isMarginalized(id); }

std::vector<WindowState> IncrementalOptimizer::windowStates() const {
  return {impl_->states.begin(), impl_->states.end()};
}

std::size_t IncrementalOptimizer::marginalizedCount() const { return impl_->marginalized_count; }

bool IncrementalOptimizer::Impl::isMarginalized(VertexId id) const {
  if (marginalized_landmarks.count(id)) return true;
  auto it = marginalized.upper_bound(id);
  if (it == marginalized.begin()) return false;
  --it;
  return id <= it->second;
}

void IncrementalOptimizer::Impl::markMarginalized(VertexId id) {
  ++marginalized_count;
  auto next = marginalized.upper_bound(id);
  if (next != marginalized.begin()) {
    auto prev = std::prev(next);
    if (id <= prev->second) return;
    if (prev->second + 1 == id) {
      prev->second = id;
      if (next != marginalized.end() && next->first == id + 1) {
        prev->second = next->second;
        marginalized.erase(next);
      }
      return;
    }
  }
  if (next != marginalized.end() && next->first == id + 1) {
    const VertexId last = next->second;
    marginalized.erase(next);
    marginalized.emplace(id, last);
    return;
  }
  marginalized.emplace(id, id);
}

// After a successful update: the states beyond the count and time bounds, and those the
// policy names, leave.
void IncrementalOptimizer::Impl::applyWindow() {
  const WindowOptions& w = options.window;
  if (!w.enabled() || states.empty()) return;
  std::set<VertexId> leaving;
  if (w.states > 0 && states.size() > w.states + w.slack) {
    for (std::size_t k = 0; k < states.size() - w.states; ++k) leaving.insert(states[k].id);
  }
  if (w.seconds > 0.0) {
    const double newest = states.back().stamp;
    for (const WindowState& s : states) {
      if (!std::isfinite(s.stamp)) {
        throw Error("window: state " + std::to_string(s.id) +
                    " has no time stamp, which a window in seconds needs");
      }
      if (s.stamp < newest - w.seconds) leaving.insert(s.id);
    }
  }
  if (w.policy) {
    for (VertexId id : w.policy(std::vector<WindowState>(states.begin(), states.end()))) {
      if (!state_ids.count(id)) {
        throw Error("window: the keyframe policy named vertex " + std::to_string(id) +
                    ", which is not a state of the window");
      }
      leaving.insert(id);
    }
  }
  if (leaving.empty()) return;
  stats.marginalized_vertices = static_cast<int>(
      marginalizeStates(std::vector<VertexId>(leaving.begin(), leaving.end())).size());
}

// The states and the landmarks that leave with them (every state they have an edge to
// leaves; none with keep_landmarks), told to on_marginalised, then marginalised out of the graph;
// the next update() rebuilds the factor.
std::vector<VertexId> IncrementalOptimizer::Impl::marginalizeStates(
    const std::vector<VertexId>& leaving_states) {
  const std::set<VertexId> leaving_set(leaving_states.begin(), leaving_states.end());
  std::set<VertexId> landmarks;  // none leave with keep_landmarks
  for (VertexId id : options.window.keep_landmarks ? std::set<VertexId>() : leaving_set) {
    for (const Edge* e : graph.vertex(id)->edges()) {
      for (VertexId other : e->vertexIds()) {
        if (state_ids.count(other) || landmarks.count(other)) continue;
        bool stays = false;  // another state that stays sees it
        for (const Edge* f : graph.vertex(other)->edges()) {
          // A prior from an earlier marginalisation is not a measurement: it ties the
          // landmark to the states that stayed then, and would keep it forever.
          if (dynamic_cast<const LinearPriorEdge*>(f)) continue;
          for (VertexId o : f->vertexIds()) {
            if (state_ids.count(o) && !leaving_set.count(o)) stays = true;
          }
        }
        if (!stays) landmarks.insert(other);
      }
    }
  }
  std::vector<VertexId> all;
  if (options.window.on_marginalised) {
    for (const WindowState& s : states) {
      if (leaving_set.count(s.id)) options.window.on_marginalised(*graph.vertex(s.id), &s);
    }
    for (VertexId id : landmarks) options.window.on_marginalised(*graph.vertex(id), nullptr);
  }
  all.assign(leaving_set.begin(), leaving_set.end());
  all.insert(all.end(), landmarks.begin(), landmarks.end());
  new_edges.erase(std::remove_if(new_edges.begin(), new_edges.end(),
                                 [&](const Edge* e) {
                                   const auto ids = e->vertexIds();
                                   return std::any_of(ids.begin(), ids.end(), [&](VertexId id) {
                                     return leaving_set.count(id) || landmarks.count(id);
                                   });
                                 }),
                  new_edges.end());
  (void)marginalizeVertices(graph, all, options.window.rank_tolerance);
  for (VertexId id : leaving_set) markMarginalized(id);
  for (VertexId id : landmarks) {
    marginalized_landmarks.insert(id);
    ++marginalized_count;
  }
  states.erase(std::remove_if(states.begin(), states.end(),
                              [&](const WindowState& s) { return leaving_set.count(s.id) != 0; }),
               states.end());
  for (VertexId id : leaving_set) state_ids.erase(id);
  needs_rebuild = true;
  version = graph.structureVersion();
  return all;
}

}  // namespace graphslam::incremental
