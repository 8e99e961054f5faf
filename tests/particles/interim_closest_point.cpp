// The particle tests' one translation unit holding the interim analytic
// closestPoint (see interim_closest_point.hpp); empty once branch `shapes` lands.
#include "interim_closest_point.hpp"
