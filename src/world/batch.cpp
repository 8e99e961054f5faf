// Batch: N worlds, one per task (include/fulcrum/batch.hpp).
#include "fulcrum/batch.hpp"

#include <string>
#include <utility>

#include "fulcrum/error.hpp"
#include "fulcrum/snapshot.hpp"
#include "fulcrum/task_system.hpp"

namespace fulcrum {

struct Batch::Impl {
    std::vector<World> worlds;
    std::vector<std::vector<std::uint8_t>> starts;  // each world's snapshot at creation, for reset()
    // Handles of each world's bodies and joints, in creation order; refreshed
    // when a world may have changed shape (world() handed out, reset).
    mutable std::vector<std::vector<BodyId>> bodies;
    mutable std::vector<std::vector<JointId>> joints;
    mutable std::vector<bool> handlesStale;
    std::vector<std::string> stepErrors;  // per world, so tasks never share one
    std::unique_ptr<TaskSystem> pool;
    int threads = 1;

    void refresh(std::size_t w) const {
        if (!handlesStale[w]) return;
        bodies[w] = worlds[w].bodies();
        joints[w] = worlds[w].joints();
        handlesStale[w] = false;
    }
    void checkIndex(std::size_t w, const char* what) const {
        if (w >= worlds.size())
            throw Error(std::string("Batch::") + what + ": world index " + std::to_string(w) + " out of range (batch of " +
                        std::to_string(worlds.size()) + " worlds)");
    }
    // The common count of bodies (or joints) per world; the arrays need one.
    template <class Handles>
    std::size_t commonCount(Handles Impl::*handles, const char* what) const {
        for (std::size_t w = 0; w < worlds.size(); ++w) refresh(w);
        const auto& all = this->*handles;
        const std::size_t n = all[0].size();
        for (std::size_t w = 1; w < all.size(); ++w) {
            if (all[w].size() != n)
                throw Error(std::string("Batch: world ") + std::to_string(w) + " has " + std::to_string(all[w].size()) +
                            " " + what + ", world 0 has " + std::to_string(n) +
                            ": the arrays need the same number in every world");
        }
        return n;
    }
    std::size_t checkedSize(std::size_t given, std::size_t perItem, const char* function) const {
        const std::size_t expected = worlds.size() * commonCount(&Impl::bodies, "bodies") * perItem;
        if (given != expected)
            throw Error(std::string("Batch::") + function + ": array of " + std::to_string(given) + " values, expected " +
                        std::to_string(expected) + " (" + std::to_string(worlds.size()) + " worlds x " +
                        std::to_string(bodies[0].size()) + " bodies x " + std::to_string(perItem) + ")");
        return expected;
    }
    void adopt(std::size_t w) {
        worlds[w].setTaskSystem(nullptr);
        worlds[w].setThreadCount(1);
        handlesStale[w] = true;
    }

    template <class Read>
    void gather(std::span<Real> out, std::size_t k, const char* function, Read read) const {
        checkedSize(out.size(), k, function);
        std::size_t i = 0;
        for (std::size_t w = 0; w < worlds.size(); ++w) {
            for (BodyId id : bodies[w]) {
                read(worlds[w], id, out.subspan(i, k));
                i += k;
            }
        }
    }
    template <class Write>
    void scatter(std::span<const Real> in, const char* function, Write write) {
        checkedSize(in.size(), 3, function);
        std::size_t i = 0;
        for (std::size_t w = 0; w < worlds.size(); ++w) {
            for (BodyId id : bodies[w]) {
                if (worlds[w].bodyType(id) != BodyType::Static) write(worlds[w], id, Vec3{in[i], in[i + 1], in[i + 2]});
                i += 3;
            }
        }
    }
};

namespace {
void put(std::span<Real> out, const Vec3& v) {
    out[0] = v.x;
    out[1] = v.y;
    out[2] = v.z;
}
}  // namespace

Batch::Batch(std::vector<World> worlds, const BatchDef& def) : impl_(std::make_unique<Impl>()) {
    if (worlds.empty()) throw Error("Batch: no worlds (a batch needs at least one)");
    if (def.threads < 1) throw Error("Batch: threads must be >= 1, got " + std::to_string(def.threads));
    Impl& m = *impl_;
    const std::size_t n = worlds.size();
    m.worlds = std::move(worlds);
    m.bodies.resize(n);
    m.joints.resize(n);
    m.handlesStale.assign(n, true);
    m.stepErrors.resize(n);
    m.starts.resize(n);
    for (std::size_t w = 0; w < n; ++w) {
        m.adopt(w);
        m.starts[w] = saveSnapshotToMemory(m.worlds[w]);
    }
    m.threads = def.threads;
    ThreadPoolDef pool;
    pool.threads = static_cast<std::uint32_t>(def.threads);
    // Worlds can differ in cost by orders of magnitude: small ranges give the
    // pool's stealing room to even them out; a range's cost (a world step) dwarfs
    // the cost of claiming it.
    pool.rangesPerWorker = 64;
    m.pool = makeThreadPool(pool);
}

Batch::~Batch() = default;
Batch::Batch(Batch&&) noexcept = default;
Batch& Batch::operator=(Batch&&) noexcept = default;

std::size_t Batch::size() const { return impl_->worlds.size(); }
int Batch::threads() const { return impl_->threads; }

World& Batch::world(std::size_t index) {
    impl_->checkIndex(index, "world");
    impl_->handlesStale[index] = true;  // the caller may add or remove bodies
    return impl_->worlds[index];
}
const World& Batch::world(std::size_t index) const {
    impl_->checkIndex(index, "world");
    return impl_->worlds[index];
}

std::size_t Batch::bodyCount() const { return impl_->commonCount(&Impl::bodies, "bodies"); }
std::size_t Batch::jointCount() const { return impl_->commonCount(&Impl::joints, "joints"); }

void Batch::step(Real dt, int steps) {
    if (steps < 0) throw Error("Batch::step: steps must be >= 0, got " + std::to_string(steps));
    Impl& m = *impl_;
    // One world per index: the world steps alone on whichever worker claims it,
    // so its bits are those of a run on its own. Errors are kept per world and
    // reported after the join (a range function must not throw into the pool).
    m.pool->parallelFor(static_cast<std::uint32_t>(m.worlds.size()), 1,
                        [&m, dt, steps](std::uint32_t begin, std::uint32_t end, std::uint32_t) noexcept {
                            for (std::uint32_t w = begin; w < end; ++w) {
                                try {
                                    for (int s = 0; s < steps; ++s) m.worlds[w].step(dt);
                                } catch (const std::exception& e) {
                                    try {
                                        m.stepErrors[w] = e.what();
                                    } catch (...) {
                                        m.stepErrors[w] = "?";
                                    }
                                }
                            }
                        });
    for (std::size_t w = 0; w < m.worlds.size(); ++w) {
        if (m.stepErrors[w].empty()) continue;
        std::string message = "Batch::step: world " + std::to_string(w) + ": " + m.stepErrors[w];
        for (std::string& e : m.stepErrors) e.clear();
        throw Error(message);
    }
}

void Batch::positions(std::span<Real> out) const {
    impl_->gather(out, 3, "positions", [](const World& w, BodyId id, std::span<Real> o) { put(o, w.position(id)); });
}
void Batch::orientations(std::span<Real> out) const {
    impl_->gather(out, 4, "orientations", [](const World& w, BodyId id, std::span<Real> o) {
        const Quat q = w.orientation(id);
        o[0] = q.w;
        o[1] = q.x;
        o[2] = q.y;
        o[3] = q.z;
    });
}
void Batch::linearVelocities(std::span<Real> out) const {
    impl_->gather(out, 3, "linearVelocities",
                  [](const World& w, BodyId id, std::span<Real> o) { put(o, w.linearVelocity(id)); });
}
void Batch::angularVelocities(std::span<Real> out) const {
    impl_->gather(out, 3, "angularVelocities",
                  [](const World& w, BodyId id, std::span<Real> o) { put(o, w.angularVelocity(id)); });
}

void Batch::setLinearVelocities(std::span<const Real> values) {
    impl_->scatter(values, "setLinearVelocities", [](World& w, BodyId id, const Vec3& v) { w.setLinearVelocity(id, v); });
}
void Batch::setAngularVelocities(std::span<const Real> values) {
    impl_->scatter(values, "setAngularVelocities",
                   [](World& w, BodyId id, const Vec3& v) { w.setAngularVelocity(id, v); });
}
void Batch::applyForces(std::span<const Real> values) {
    impl_->scatter(values, "applyForces", [](World& w, BodyId id, const Vec3& f) { w.applyForceAtCenter(id, f); });
}

void Batch::setJointMotorSpeeds(std::span<const Real> values) {
    Impl& m = *impl_;
    const std::size_t perWorld = jointCount();
    if (values.size() != m.worlds.size() * perWorld)
        throw Error("Batch::setJointMotorSpeeds: array of " + std::to_string(values.size()) + " values, expected " +
                    std::to_string(m.worlds.size() * perWorld) + " (" + std::to_string(m.worlds.size()) + " worlds x " +
                    std::to_string(perWorld) + " joints)");
    std::size_t i = 0;
    for (std::size_t w = 0; w < m.worlds.size(); ++w) {
        for (JointId id : m.joints[w]) {
            const JointDef& def = m.worlds[w].jointDef(id);
            if (def.type == JointType::Hinge || def.type == JointType::Slider) {
                JointMotor motor = def.motor;
                motor.speed = values[i];
                m.worlds[w].setJointMotor(id, motor);
            }
            ++i;
        }
    }
}

void Batch::reset(std::size_t index) {
    impl_->checkIndex(index, "reset");
    reset(index, impl_->starts[index]);
}

void Batch::reset(std::size_t index, std::span<const std::uint8_t> snapshot) {
    impl_->checkIndex(index, "reset");
    World restored = loadSnapshotFromMemory(snapshot, nullptr, "Batch::reset snapshot");
    impl_->worlds[index] = std::move(restored);
    impl_->adopt(index);
}

std::vector<std::uint8_t> Batch::snapshot(std::size_t index) const {
    impl_->checkIndex(index, "snapshot");
    return saveSnapshotToMemory(impl_->worlds[index]);
}

}  // namespace fulcrum
