// Explicit instantiation of every SSV pair distance for float and double, compiled with
// -Wall -Wextra -Werror -Wdouble-promotion -Wshadow (tests/CMakeLists.txt): the headers must stay
// clean under the flags the generated code and firmware builds use. Linked into test_ssv_distance.
#include "mbgen/collision/ssv_distance.hpp"

namespace mbgen::collision {
#define MBGEN_SSV_INSTANTIATE(S)                                                          \
  template SsvDistance<S> ssv_distance(const PointSsv<S>&, const PointSsv<S>&);          \
  template SsvDistance<S> ssv_distance(const PointSsv<S>&, const LineSsv<S>&);           \
  template SsvDistance<S> ssv_distance(const PointSsv<S>&, const TriangleSsv<S>&);       \
  template SsvDistance<S> ssv_distance(const LineSsv<S>&, const LineSsv<S>&);            \
  template SsvDistance<S> ssv_distance(const LineSsv<S>&, const TriangleSsv<S>&);        \
  template SsvDistance<S> ssv_distance(const TriangleSsv<S>&, const TriangleSsv<S>&);
MBGEN_SSV_INSTANTIATE(float)
MBGEN_SSV_INSTANTIATE(double)
#undef MBGEN_SSV_INSTANTIATE
}  // namespace mbgen::collision
