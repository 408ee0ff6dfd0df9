// SPDX-License-Identifier: MIT
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <memory>

#include "graphslam/core/linear_solver.h"
#include "graphslam/core/robust_kernel.h"
#include "graphslam/core/type_registry.h"
#include "graphslam/support/error.h"

namespace graphslam {

namespace {
/// " (by 'A' and again by 'B')" naming the two registrations of a name, when known.
std::string twiceBy(const std::string& first, const std::string& second) {
  if (first.empty() && second.empty()) return {};
  auto label = [](const std::string& origin) {
    return origin.empty() ? std::string("the program itself") : "'" + origin + "'";
  };
  return " (by " + label(first) + " and again by " + label(second) + ")";
}

void checkName(const std::string& name, const char* what) {
  if (name.empty()) throw RegistryError(std::string("empty ") + what);
  if (std::any_of(name.begin(), name.end(),
                  [](unsigned char c) { return std::isspace(c) || !std::isprint(c); })) {
    throw RegistryError(std::string(what) + " '" + name + "' contains whitespace");
  }
}
}  // namespace

void TypeRegistry::addEntry(Entry entry, std::type_index type) {
  const std::string& tag = entry.tag;
  checkName(tag, "type tag");
  if ((entry.kind == Kind::kVertex && !entry.make_vertex) ||
      (entry.kind == Kind::kEdge && !entry.make_edge) ||
      (entry.kind == Kind::kParameter && !entry.make_parameter)) {
    throw RegistryError("null factory for type tag '" + tag + "'");
  }
  if (const auto it = entries_.find(tag); it != entries_.end()) {
    throw RegistryError("type tag '" + tag + "' is already registered" +
                        twiceBy(it->second.origin, origin_));
  }
  auto t = tags_.find(type);
  if (t != tags_.end()) {
    throw RegistryError("type for tag '" + tag + "' is already registered as '" + t->second + "'");
  }
  entry.origin = origin_;
  tags_.emplace(type, tag);
  entries_.emplace(tag, std::move(entry));
}

void TypeRegistry::registerVertexFactory(const std::string& tag, std::type_index type,
                                         std::function<std::unique_ptr<Vertex>()> factory) {
  addEntry(Entry{tag, Kind::kVertex, origin_, std::move(factory), {}, {}}, type);
}

void TypeRegistry::registerEdgeFactory(const std::string& tag, std::type_index type,
                                       std::function<std::unique_ptr<Edge>()> factory) {
  addEntry(Entry{tag, Kind::kEdge, origin_, {}, std::move(factory), {}}, type);
}

const TypeRegistry::Entry* TypeRegistry::find(const std::string& tag) const {
  auto it = entries_.find(tag);
  return it == entries_.end() ? nullptr : &it->second;
}

std::unique_ptr<Vertex> TypeRegistry::createVertex(const std::string& tag) const {
  const Entry* e = find(tag);
  if (!e || e->kind != Kind::kVertex) throw RegistryError("unknown vertex tag '" + tag + "'");
  return e->make_vertex();
}

std::unique_ptr<Edge> TypeRegistry::createEdge(const std::string& tag) const {
  const Entry* e = find(tag);
  if (!e || e->kind != Kind::kEdge) throw RegistryError("unknown edge tag '" + tag + "'");
  return e->make_edge();
}

const std::string* TypeRegistry::tagOf(const Vertex& v) const {
  auto it = tags_.find(std::type_index(typeid(v)));
  return it == tags_.end() ? nullptr : &it->second;
}

std::unique_ptr<Parameter> TypeRegistry::createParameter(const std::string& tag) const {
  const Entry* e = find(tag);
  if (!e || e->kind != Kind::kParameter) throw RegistryError("unknown parameter tag '" + tag + "'");
  return e->make_parameter();
}

const std::string* TypeRegistry::tagOf(const Parameter& p) const {
  auto it = tags_.find(std::type_index(typeid(p)));
  return it == tags_.end() ? nullptr : &it->second;
}

const std::string* TypeRegistry::tagOf(const Edge& e) const {
  auto it = tags_.find(std::type_index(typeid(e)));
  return it == tags_.end() ? nullptr : &it->second;
}

std::vector<const TypeRegistry::Entry*> TypeRegistry::entries() const {
  std::vector<const Entry*> out;
  for (const auto& [tag, entry] : entries_) out.push_back(&entry);
  return out;
}

void KernelRegistry::registerKernel(const std::string& name, double default_width,
                                    RobustKernelFactory factory) {
  checkName(name, "kernel name");
  if (!factory) throw RegistryError("null factory for kernel '" + name + "'");
  if (!(default_width > 0.0) || !std::isfinite(default_width)) {
    throw RegistryError("kernel '" + name + "': default width must be positive and finite");
  }
  if (const auto it = entries_.find(name); it != entries_.end()) {
    throw RegistryError("kernel '" + name + "' is already registered" +
                        twiceBy(it->second.origin, origin_));
  }
  entries_.emplace(name, Entry{name, default_width, origin_, std::move(factory)});
}

const KernelRegistry::Entry* KernelRegistry::find(const std::string& name) const {
  auto it = entries_.find(name);
  return it == entries_.end() ? nullptr : &it->second;
}

std::shared_ptr<RobustKernel> KernelRegistry::create(const std::string& name, double width) const {
  const Entry* k = find(name);
  if (!k) {
    std::string known;
    for (const auto& [n, entry] : entries_) known += (known.empty() ? "" : ", ") + n;
    throw RegistryError(
        "unknown robust kernel '" + name + "'" +
        (known.empty() ? std::string(" (none is registered)") : " (known: " + known + ")"));
  }
  if (std::isnan(width)) width = k->default_width;
  if (!(width > 0.0) || !std::isfinite(width)) {
    throw RegistryError("robust kernel '" + name + "': width must be positive and finite, got " +
                        std::to_string(width));
  }
  std::shared_ptr<RobustKernel> kernel = k->make(width);
  if (!kernel) throw RegistryError("robust kernel '" + name + "': its factory returned nothing");
  return kernel;
}

std::vector<const KernelRegistry::Entry*> KernelRegistry::entries() const {
  std::vector<const Entry*> out;
  for (const auto& [name, entry] : entries_) out.push_back(&entry);
  return out;
}

const char* toString(LinearSolverStatus status) {
  switch (status) {
    case LinearSolverStatus::kSuccess:
      return "success";
    case LinearSolverStatus::kNotPositiveDefinite:
      return "not positive definite";
    case LinearSolverStatus::kSingular:
      return "singular";
    case LinearSolverStatus::kFailure:
      return "failure";
  }
  return "unknown";
}

const char* toString(Ordering ordering) {
  switch (ordering) {
    case Ordering::kDefault:
      return "default";
    case Ordering::kNatural:
      return "natural";
    case Ordering::kAmd:
      return "amd";
    case Ordering::kColamd:
      return "colamd";
    case Ordering::kMetis:
      return "metis";
    case Ordering::kRcm:
      return "rcm";
  }
  return "unknown";
}

bool parseOrdering(const std::string& text, Ordering& ordering) {
  for (Ordering o : {Ordering::kDefault, Ordering::kNatural, Ordering::kAmd, Ordering::kColamd,
                     Ordering::kMetis, Ordering::kRcm}) {
    if (text == toString(o)) {
      ordering = o;
      return true;
    }
  }
  return false;
}

namespace {
LinearSolverResult notThisForm(const LinearSolver& s, const char* call) {
  return LinearSolverResult::failure(
      LinearSolverStatus::kFailure,
      s.name() + " does not take " +
          (s.form() == SystemForm::kJacobian ? "the normal equations" : "the Jacobian form") +
          " (" + call + ")");
}
}  // namespace

LinearSolverResult LinearSolver::analyze(const SparseStructure&) {
  return notThisForm(*this, "analyze");
}
LinearSolverResult LinearSolver::factorize(const double*) {
  return notThisForm(*this, "factorize");
}
LinearSolverResult LinearSolver::solve(const double*, double*) {
  return notThisForm(*this, "solve");
}
LinearSolverResult LinearSolver::analyzeJacobian(const JacobianStructure&) {
  return notThisForm(*this, "analyzeJacobian");
}
LinearSolverResult LinearSolver::factorizeJacobian(const double*) {
  return notThisForm(*this, "factorizeJacobian");
}
LinearSolverResult LinearSolver::solveJacobian(const double*, double*) {
  return notThisForm(*this, "solveJacobian");
}

void SolverRegistry::registerSolver(const std::string& name, const std::string& description,
                                    SystemForm form, std::vector<Ordering> orderings,
                                    Factory factory) {
  checkName(name, "solver name");
  if (name.find(':') != std::string::npos) {
    throw RegistryError("solver name '" + name + "' contains ':' (it separates the ordering)");
  }
  if (!factory) throw RegistryError("null factory for solver '" + name + "'");
  if (orderings.empty()) throw RegistryError("solver '" + name + "' lists no ordering");
  if (const auto it = entries_.find(name); it != entries_.end()) {
    throw RegistryError("solver '" + name + "' is already registered" +
                        twiceBy(it->second.origin, origin_));
  }
  entries_.emplace(
      name, Entry{name, description, origin_, form, std::move(orderings), std::move(factory)});
}

void SolverRegistry::registerSolver(const std::string& name, const std::string& description,
                                    SimpleFactory factory) {
  if (!factory) throw RegistryError("null factory for solver '" + name + "'");
  registerSolver(name, description, SystemForm::kNormalEquations, {Ordering::kDefault},
                 [f = std::move(factory)](const LinearSolverOptions&) { return f(); });
}

const SolverRegistry::Entry* SolverRegistry::find(const std::string& name) const {
  auto it = entries_.find(name);
  return it == entries_.end() ? nullptr : &it->second;
}

namespace {
/// Splits "name:ordering"; the ordering part is empty when absent.
std::pair<std::string, std::string> splitSpec(const std::string& spec) {
  const auto colon = spec.find(':');
  if (colon == std::string::npos) return {spec, ""};
  return {spec.substr(0, colon), spec.substr(colon + 1)};
}
}  // namespace

bool SolverRegistry::contains(const std::string& spec) const {
  const auto [name, ord] = splitSpec(spec);
  const Entry* e = find(name);
  if (!e) return false;
  if (ord.empty()) return true;
  Ordering o;
  if (!parseOrdering(ord, o)) return false;
  return o == Ordering::kDefault ||
         std::find(e->orderings.begin(), e->orderings.end(), o) != e->orderings.end();
}

std::unique_ptr<LinearSolver> SolverRegistry::create(const std::string& spec) const {
  const auto [name, ord] = splitSpec(spec);
  LinearSolverOptions options;
  if (!ord.empty() && !parseOrdering(ord, options.ordering)) {
    throw RegistryError("unknown ordering '" + ord + "' in solver '" + spec +
                        "' (known: natural, amd, colamd, metis, default)");
  }
  return create(name, options);
}

std::unique_ptr<LinearSolver> SolverRegistry::create(const std::string& name,
                                                     const LinearSolverOptions& options) const {
  const Entry* e = find(name);
  if (!e) {
    std::string known;
    for (const auto& [n, entry] : entries_) known += (known.empty() ? "" : ", ") + n;
    throw RegistryError("unknown linear solver '" + name +
                        "' (known: " + (known.empty() ? "none" : known) + ")");
  }
  LinearSolverOptions opts = options;
  if (opts.ordering == Ordering::kDefault) opts.ordering = e->orderings.front();
  if (std::find(e->orderings.begin(), e->orderings.end(), opts.ordering) == e->orderings.end()) {
    std::string accepted;
    for (Ordering o : e->orderings)
      accepted += (accepted.empty() ? "" : ", ") + std::string(toString(o));
    throw RegistryError("solver '" + name + "' does not offer the ordering '" +
                        toString(opts.ordering) + "' (it offers: " + accepted + ")");
  }
  return e->factory(opts);
}

std::vector<const SolverRegistry::Entry*> SolverRegistry::entries() const {
  std::vector<const Entry*> out;
  for (const auto& [name, entry] : entries_) out.push_back(&entry);
  return out;
}

void SolverRegistry::registerOrdering(Ordering ordering, OrderingFunction function) {
  if (!function)
    throw RegistryError(std::string("null ordering function for ") + toString(ordering));
  if (!orderings_.emplace(ordering, std::move(function)).second) {
    throw RegistryError(std::string("ordering ") + toString(ordering) + " is already registered");
  }
}

const SolverRegistry::OrderingFunction* SolverRegistry::ordering(Ordering ordering) const {
  const auto it = orderings_.find(ordering);
  return it == orderings_.end() ? nullptr : &it->second;
}

}  // namespace graphslam
