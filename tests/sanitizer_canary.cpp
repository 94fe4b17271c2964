// The sanitized subset's canary (ctest sanitizers.canary, cmake/mbgen_sanitizers.cmake): issue 61's
// report, on purpose. Eigen's sized LLT constructor leaves the decomposition's status unset, and
// copying the decomposition reads that status: UndefinedBehaviorSanitizer reports "load of value
// ..., which is not a valid value for type 'ComputationInfo'" and ends the run. The test passes
// only on that report, so it fails when the subset is built without the sanitizers.
#include <Eigen/Cholesky>

#include <cstdio>
#include <cstring>
#include <new>

int main() {
  using Llt = Eigen::LLT<Eigen::MatrixXd>;
  // What an unset member holds in a reused block: bytes that are no ComputationInfo (0 to 3).
  alignas(Llt) unsigned char storage[sizeof(Llt)];
  std::memset(storage, 0xA5, sizeof storage);
  Llt* never_computed = new (storage) Llt(3);
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"  // the unset status is the point
  const Llt copy(*never_computed);  // the implicit copy loads the unset status
#pragma GCC diagnostic pop
  // The copy's status is printed, so that its load is used.
  std::printf("copied a never-computed LLT of size %ld, status %d, without a report: the sanitizers are off\n",
              static_cast<long>(copy.rows()), static_cast<int>(copy.info()));
  never_computed->~Llt();
  return 0;
}
