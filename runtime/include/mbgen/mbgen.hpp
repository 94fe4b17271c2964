#pragma once
// The generic (interpreted) runtime: every algorithm, for any scalar type.
#include "mbgen/algorithm/aba.hpp"
#include "mbgen/algorithm/center_of_mass.hpp"
#include "mbgen/algorithm/centroidal.hpp"
#include "mbgen/algorithm/configuration.hpp"
#include "mbgen/algorithm/crba.hpp"
#include "mbgen/algorithm/energy.hpp"
#include "mbgen/algorithm/integrator.hpp"
#include "mbgen/algorithm/jacobian.hpp"
#include "mbgen/algorithm/kinematics.hpp"
#include "mbgen/algorithm/rnea.hpp"
#include "mbgen/data.hpp"
#include "mbgen/model.hpp"
