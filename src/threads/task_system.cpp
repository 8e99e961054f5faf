// The public entry point to the built-in pool; the pool itself lives in
// threads/thread_pool.cpp so the public header stays free of <thread>/<mutex>.
#include "fulcrum/task_system.hpp"

#include "threads/thread_pool.hpp"

namespace fulcrum {

std::unique_ptr<TaskSystem> makeThreadPool(const ThreadPoolDef& def) {
    return std::make_unique<detail::ThreadPool>(def);
}

}  // namespace fulcrum
