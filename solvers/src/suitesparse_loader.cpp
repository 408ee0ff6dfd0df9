// SPDX-License-Identifier: MIT
// The solvers library's entry points into the SuiteSparse backend (suitesparse.h): the backend
// library is loaded on the first call, from the folder this library was loaded from. A
// static build links the backend in and calls it directly.
#include <dlfcn.h>

#include <string>

#include "graphslam/support/error.h"
#include "suitesparse.h"
#include "suitesparse_backend.h"

namespace graphslam::solvers {

namespace {

#ifdef GRAPHSLAM_SUITESPARSE_BACKEND_FILE
/// The backend library next to this one (libgraphslam_solvers's own folder).
std::string backendPath() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&backendPath), &info) == 0 || !info.dli_fname) {
    return GRAPHSLAM_SUITESPARSE_BACKEND_FILE;
  }
  std::string self = info.dli_fname;
  const auto slash = self.find_last_of('/');
  return (slash == std::string::npos ? std::string() : self.substr(0, slash + 1)) +
         GRAPHSLAM_SUITESPARSE_BACKEND_FILE;
}

const suitesparse::Backend& load() {
  const std::string path = backendPath();
  // Kept loaded for the process's lifetime: solvers made by it may live until the end.
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
  if (!handle) {
    const char* why = dlerror();
    throw Error("the SuiteSparse solvers are not available: cannot load " + path + ": " +
                (why ? why : "unknown reason"));
  }
  using Entry = const suitesparse::Backend* (*)();
  auto entry = reinterpret_cast<Entry>(dlsym(handle, "graphslam_solvers_suitesparse_backend"));
  if (!entry) throw Error(path + " is not graphslam's SuiteSparse backend (no entry)");
  return *entry();
}
#else
const suitesparse::Backend& load() { return *graphslam_solvers_suitesparse_backend(); }
#endif

const suitesparse::Backend& backend() {
  static const suitesparse::Backend& table = load();  // retried after a throw
  return table;
}

}  // namespace

std::unique_ptr<detail::OrderedSolver> makeCholmodSolver(bool supernodal, Ordering ordering,
                                                         bool prepermuted_lower,
                                                         const CholmodOptions& options) {
  return backend().cholmod(supernodal, ordering, prepermuted_lower, options);
}

std::unique_ptr<detail::OrderedSolver> makeCholmodComplexSolver(bool supernodal, Ordering ordering,
                                                                bool prepermuted_lower,
                                                                const CholmodOptions& options) {
  return backend().cholmod_complex(supernodal, ordering, prepermuted_lower, options);
}

std::unique_ptr<LinearSolver> makeCsparseSolver(Ordering ordering,
                                                std::shared_ptr<OrderingCache> cache) {
  return backend().csparse(ordering, std::move(cache));
}

std::unique_ptr<LinearSolver> makeUmfpackSolver(Ordering ordering,
                                                std::shared_ptr<OrderingCache> cache) {
  return backend().umfpack(ordering, std::move(cache));
}

std::unique_ptr<LinearSolver> makeSpqrSolver(Ordering ordering) { return backend().spqr(ordering); }

std::vector<int> metisBlockOrdering(const detail::BlockGraph& g) { return backend().metis(g); }

std::unique_ptr<OrderedFactor> makeOrderedSupernodalFactor() { return backend().ordered_factor(); }

std::vector<int> metisVertexSeparator(const std::vector<int>& column_starts,
                                      const std::vector<int>& rows) {
  return backend().metis_separator(column_starts, rows);
}

}  // namespace graphslam::solvers
