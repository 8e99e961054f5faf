// Springs: damped force elements between anchor points (spring.hpp).
#include "dynamics/validation.hpp"
#include "world/world_impl.hpp"

namespace fulcrum {

using detail::fail;
using detail::kNoIndex;
using detail::Subject;

detail::SpringData& WorldImpl::resolveSpring(SpringId id, const char* where) {
    return const_cast<detail::SpringData&>(static_cast<const WorldImpl*>(this)->resolveSpring(id, where));
}

const detail::SpringData& WorldImpl::resolveSpring(SpringId id, const char* where) const {
    return detail::resolveHandle(springs, id, where, "SpringId", "spring");
}

SpringId World::createSpring(const SpringDef& def) {
    WorldImpl& w = *impl_;
    const std::uint32_t slot = w.springs.nextSlot();
    const Subject who{"spring", "", slot};
    auto endpoint = [&](BodyId id, const char* field) -> std::uint32_t {
        if (id.isNull()) return kNoIndex;
        if (!w.isLive(id)) {
            fail(who, field, "refers to a body that does not exist or was destroyed (index " + std::to_string(id.index) +
                                 ", generation " + std::to_string(id.generation) + ")");
        }
        return w.bodySlots[id.index].dense;
    };
    const std::uint32_t a = endpoint(def.bodyA, "bodyA");
    const std::uint32_t b = endpoint(def.bodyB, "bodyB");
    if (a == kNoIndex && b == kNoIndex) fail(who, "bodyA/bodyB", "are both the static world: a spring needs at least one body");
    if (a != kNoIndex && a == b) fail(who, "bodyB", "is the same body as bodyA");
    detail::requireFinite(who, "anchorA", def.anchorA);
    detail::requireFinite(who, "anchorB", def.anchorB);
    detail::requireNonNegative(who, "restLength", def.restLength);
    detail::requireNonNegative(who, "stiffness", def.stiffness);
    detail::requireNonNegative(who, "damping", def.damping);

    auto toLocal = [&](std::uint32_t dense, const Vec3& p) {
        return dense == kNoIndex ? p : inverseRotate(w.motion[dense].q, p - w.motion[dense].com);
    };
    detail::SpringData& s = w.springs.add();
    s.bodyA = def.bodyA;
    s.bodyB = def.bodyB;
    s.localA = toLocal(a, def.anchorA);
    s.localB = toLocal(b, def.anchorB);
    s.restLength = def.restLength;
    s.stiffness = def.stiffness;
    s.damping = def.damping;
    return w.springs.handleOf(slot);
}

void World::destroySpring(SpringId id) {
    (void)impl_->resolveSpring(id, "World::destroySpring");
    impl_->springs.remove(id.index);
}

bool World::isValid(SpringId id) const { return impl_->springs.isLive(id); }

std::size_t World::springCount() const { return impl_->springs.liveCount(); }

Real World::springLength(SpringId id) const {
    const WorldImpl& w = *impl_;
    const detail::SpringData& s = w.resolveSpring(id, "World::springLength");
    return distance(w.anchorWorld(w.denseOrNone(s.bodyA), s.localA), w.anchorWorld(w.denseOrNone(s.bodyB), s.localB));
}

}  // namespace fulcrum
