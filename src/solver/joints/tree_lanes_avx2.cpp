// The tree lanes' kernel compiled with -mavx2 (CMakeLists.txt, this file
// only, never -mfma: the lanes must round as the scalar code; tree_lanes.hpp).
// Used only where the CPU has AVX2 (JointTreeSolver::setLanes).
#if defined(__AVX2__)
#define FULCRUM_TREE_LANES_NS tree_lanes_avx2
#define FULCRUM_TREE_LANES_FN solveTreeLanesAvx2
#define FULCRUM_TREE_LANES_FACTOR_FN factorTreeLanesAvx2
#define FULCRUM_TREE_LANES_LEAVE() _mm256_zeroupper()  // back to SSE code without the transition penalty
#include <immintrin.h>
#include "solver/joints/tree_lanes_kernels.hpp"

namespace fulcrum::detail {
bool treeLanesAvx2Compiled() { return true; }
}  // namespace fulcrum::detail
#else
#include "solver/joints/tree_lanes.hpp"

namespace fulcrum::detail {
bool treeLanesAvx2Compiled() { return false; }
void solveTreeLanesAvx2(const TreeLaneNode* nodes, std::uint32_t count, TreeLane4* data) {
    solveTreeLanes(nodes, count, data);
}
unsigned factorTreeLanesAvx2(const TreeLaneNode* nodes, std::uint32_t count, TreeLane4* data) {
    return factorTreeLanes(nodes, count, data);
}
}  // namespace fulcrum::detail
#endif
