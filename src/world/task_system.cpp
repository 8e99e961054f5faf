// The public entry point to the built-in pool; the pool itself lives in
// world/thread_pool.cpp so the public header stays free of <thread>/<mutex>.
#include "fulcrum/task_system.hpp"

#include "world/thread_pool.hpp"

namespace fulcrum {

std::unique_ptr<TaskSystem> makeThreadPool(const ThreadPoolDef& def) {
    return std::make_unique<detail::ThreadPool>(def);
}

}  // namespace fulcrum
