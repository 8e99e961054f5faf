// The tree lanes' kernel for the target's baseline (tree_lanes.hpp).
#define FULCRUM_TREE_LANES_NS tree_lanes_base
#define FULCRUM_TREE_LANES_FN solveTreeLanes
#define FULCRUM_TREE_LANES_FACTOR_FN factorTreeLanes
#include "solver/joints/tree_lanes_kernels.hpp"
