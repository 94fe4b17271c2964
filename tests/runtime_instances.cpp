// The one instance of each algorithm runtime_instances.hpp declares.
#define MBGEN_TEST_INSTANCE template
#include "runtime_instances.hpp"
