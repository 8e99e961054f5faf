// Bullet 3 (Debian's libbullet-dev, single precision) running bench/scenes.hpp
// at its defaults: btDiscreteDynamicsWorld with btDbvtBroadphase and
// btSequentialImpulseConstraintSolver (10 iterations, split impulse on for
// penetration recovery), one stepSimulation(dt, 0) per step (exactly one
// internal step of dt), sleeping (deactivation) on unless the scene turns it
// off. The cloth is a btSoftBody patch in a btSoftRigidDynamicsWorld.
#include <BulletSoftBody/btSoftBodyHelpers.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <vector>

#include "peers.hpp"

namespace bench {
namespace {

btVector3 bt(V3 v) { return {static_cast<btScalar>(v.x), static_cast<btScalar>(v.y), static_cast<btScalar>(v.z)}; }
V3 toV3(const btVector3& v) { return {v.x(), v.y(), v.z()}; }

class BulletEngine final : public Engine {
public:
    std::string name() const override { return "Bullet"; }
    std::string settings() const override {
        return "Bullet 3.24 (float): btDiscreteDynamicsWorld, btDbvtBroadphase, btSequentialImpulseConstraintSolver "
               "(10 iterations, split impulse), stepSimulation(dt, 0); each body friction sqrt(mu) (Bullet multiplies "
               "the two); sleeping (deactivation) on except the pyramids and probes; no gyroscopic term (Bullet's "
               "default); cloth: btSoftBody::CreatePatch with diagonals + generateBendingConstraints(2), 1 position "
               "iteration, collision margin 0.02 m";
    }

    ~BulletEngine() override {
        if (world_ == nullptr) return;
        for (btTypedConstraint* c : constraints_) world_->removeConstraint(c);
        for (int g = 0; g < static_cast<int>(groupBodies_.size()); ++g) destroyGroup(g);
        for (const auto& b : bodies_) world_->removeRigidBody(b.get());
        for (const auto& b : gridBodies_) world_->removeRigidBody(b.get());
        if (cloth_ != nullptr) static_cast<btSoftRigidDynamicsWorld*>(world_.get())->removeSoftBody(cloth_);
        delete cloth_;
        for (btTypedConstraint* c : constraints_) delete c;
    }

    bool build(const SceneSpec& scene, std::string& /*why*/) override {
        scene_ = &scene;
        if (scene.cloth.n > 0) {
            auto config = std::make_unique<btSoftBodyRigidBodyCollisionConfiguration>();
            dispatcher_ = std::make_unique<btCollisionDispatcher>(config.get());
            config_ = std::move(config);
        } else {
            config_ = std::make_unique<btDefaultCollisionConfiguration>();
            dispatcher_ = std::make_unique<btCollisionDispatcher>(config_.get());
        }
        broadphase_ = std::make_unique<btDbvtBroadphase>();
        solver_ = std::make_unique<btSequentialImpulseConstraintSolver>();
        if (scene.cloth.n > 0) {
            world_ = std::make_unique<btSoftRigidDynamicsWorld>(dispatcher_.get(), broadphase_.get(), solver_.get(), config_.get());
        } else {
            world_ = std::make_unique<btDiscreteDynamicsWorld>(dispatcher_.get(), broadphase_.get(), solver_.get(), config_.get());
        }
        world_->setGravity(bt(scene.gravity));
        world_->getPairCache()->setOverlapFilterCallback(&groupFilter_);

        for (const BodySpec& b : scene.bodies) {
            bodies_.push_back(makeBody(b));
            centerOffsets_.push_back(centerOffset(b));
        }
        onPath_.assign(scene.bodies.size(), false);
        for (const KinematicPath& path : scene.kinematicPaths) onPath_[static_cast<std::size_t>(path.body)] = true;
        if (scene.staticGrid.nx > 0) {
            const StaticGrid& g = scene.staticGrid;
            BodySpec tile;
            tile.isStatic = true;
            tile.half = g.half;
            const double halfX = 0.5 * g.cell * g.nx, halfZ = 0.5 * g.cell * g.nz;
            for (int i = 0; i < g.nx; ++i) {
                for (int k = 0; k < g.nz; ++k) {
                    tile.position = {-halfX + (i + 0.5) * g.cell, g.y, -halfZ + (k + 0.5) * g.cell};
                    gridBodies_.push_back(makeBody(tile));
                }
            }
        }
        groupBodies_.resize(scene.groups.size());
        groupJoints_.resize(scene.groups.size());
        for (const JointSpec& j : scene.joints) {
            if (j.localFrames || j.type != JointSpec::Type::Ball) {
                constraints_.push_back(makeJoint(j, j.a < 0 ? nullptr : bodies_[static_cast<std::size_t>(j.a)].get(),
                                                 *bodies_[static_cast<std::size_t>(j.b)]));
                continue;
            }
            btRigidBody& b = *bodies_[static_cast<std::size_t>(j.b)];
            const btVector3 pivotB = b.getCenterOfMassTransform().inverse() * bt(j.anchor);
            btTypedConstraint* c = nullptr;
            if (j.a < 0) {
                c = new btPoint2PointConstraint(b, pivotB);
            } else {
                btRigidBody& a = *bodies_[static_cast<std::size_t>(j.a)];
                c = new btPoint2PointConstraint(a, b, a.getCenterOfMassTransform().inverse() * bt(j.anchor), pivotB);
            }
            constraints_.push_back(c);
            world_->addConstraint(c, /*disableCollisionsBetweenLinkedBodies=*/true);
        }
        if (scene.cloth.n > 0) buildCloth(scene.cloth);
        return true;
    }

    void step() override {
        // Kinematic bodies move at their velocities (those on a path: moveKinematic):
        // Bullet reads their pose from the motion state each step.
        const auto dt = static_cast<btScalar>(scene_->dt);
        for (std::size_t i = 0; i < bodies_.size(); ++i) {
            if (!scene_->bodies[i].isKinematic || onPath_[i]) continue;
            btRigidBody& b = *bodies_[i];
            btTransform xf;
            btTransformUtil::integrateTransform(b.getWorldTransform(), bt(scene_->bodies[i].linearVelocity),
                                                bt(scene_->bodies[i].angularVelocity), dt, xf);
            b.getMotionState()->setWorldTransform(xf);
        }
        world_->stepSimulation(dt, 0, dt);
    }

    void createGroup(int group) override {
        const BodyGroup& g = scene_->groups[static_cast<std::size_t>(group)];
        auto& bodies = groupBodies_[static_cast<std::size_t>(group)];
        for (const BodySpec& b : g.bodies) bodies.push_back(makeBody(b));
        for (const JointSpec& j : g.joints) {
            groupJoints_[static_cast<std::size_t>(group)].push_back(
                makeJoint(j, j.a < 0 ? nullptr : bodies[static_cast<std::size_t>(j.a)].get(), *bodies[static_cast<std::size_t>(j.b)]));
        }
    }
    void destroyGroup(int group) override {
        for (btTypedConstraint* c : groupJoints_[static_cast<std::size_t>(group)]) {
            world_->removeConstraint(c);
            delete c;
        }
        for (const auto& b : groupBodies_[static_cast<std::size_t>(group)]) {
            world_->removeRigidBody(b.get());
        }
        groupJoints_[static_cast<std::size_t>(group)].clear();
        groupBodies_[static_cast<std::size_t>(group)].clear();
    }
    std::vector<V3> dynamicPositions() const override {
        std::vector<V3> out;
        for (std::size_t i = 0; i < bodies_.size(); ++i) {
            if (!scene_->bodies[i].isStatic && !scene_->bodies[i].isKinematic) out.push_back(toV3(bodies_[i]->getWorldTransform().getOrigin()));
        }
        for (const auto& group : groupBodies_) {
            for (const auto& b : group) out.push_back(toV3(b->getWorldTransform().getOrigin()));
        }
        return out;
    }

    void moveKinematic(std::size_t i, V3 origin, double) override {
        // Bullet turns the motion state's new transform into the kinematic body's velocity for the step.
        bodies_[i]->getMotionState()->setWorldTransform(btTransform(btQuaternion::getIdentity(), bt(origin) + centerOffsets_[i]));
    }

    BodyState body(std::size_t i) const override {
        const btRigidBody& b = *bodies_[i];
        const btQuaternion q = b.getOrientation();
        // The body origin (the centre of mass less a compound's shift).
        return {toV3(b.getCenterOfMassPosition() - quatRotate(q, centerOffsets_[i])), {q.w(), q.x(), q.y(), q.z()},
                toV3(b.getLinearVelocity()), toV3(b.getAngularVelocity())};
    }
    bool asleep(std::size_t i) const override { return bodies_[i]->getActivationState() == ISLAND_SLEEPING; }

    double deepestPenetration() const override {
        double deepest = 0;
        for (int m = 0; m < dispatcher_->getNumManifolds(); ++m) {
            const btPersistentManifold* manifold = dispatcher_->getManifoldByIndexInternal(m);
            for (int c = 0; c < manifold->getNumContacts(); ++c) {
                deepest = std::max(deepest, static_cast<double>(-manifold->getContactPoint(c).getDistance()));
            }
        }
        return deepest;
    }

    std::vector<V3> clothParticles() const override {
        std::vector<V3> out;
        if (cloth_ == nullptr) return out;
        for (int i = 0; i < cloth_->m_nodes.size(); ++i) out.push_back(toV3(cloth_->m_nodes[i].m_x));
        return out;
    }

private:
    btCollisionShape* partShape(const ShapePart& p) {
        switch (p.kind) {
            case ShapePart::Kind::Box: return addShape(std::make_unique<btBoxShape>(bt(p.half)));
            case ShapePart::Kind::Sphere: return addShape(std::make_unique<btSphereShape>(static_cast<btScalar>(p.half.x)));
            case ShapePart::Kind::Capsule:
                return addShape(std::make_unique<btCapsuleShape>(static_cast<btScalar>(p.half.x), static_cast<btScalar>(2 * p.half.y)));
            case ShapePart::Kind::Hull: {
                auto h = std::make_unique<btConvexHullShape>();
                for (const V3& v : p.points) h->addPoint(bt(v), false);
                h->recalcLocalAabb();
                h->optimizeConvexHull();
                return addShape(std::move(h));
            }
        }
        return nullptr;
    }

    // One shape per distinct description (as the Fulcrum side shares them).
    btCollisionShape* shapeFor(const BodySpec& b) {
        if (b.mesh >= 0) {
            auto& shape = meshShapes_[b.mesh];
            if (shape == nullptr) shape = buildMesh(*scene_->meshes[static_cast<std::size_t>(b.mesh)]);
            return shape;
        }
        if (b.kind == BodySpec::Kind::SharedCompound && b.parts.empty()) {
            if (sharedCompound_ == nullptr) sharedCompound_ = buildCompound(scene_->sharedCompoundHulls, sharedCompoundCenter_);
            return sharedCompound_;
        }
        std::vector<double> key{double(static_cast<int>(b.kind)), b.half.x, b.half.y, b.half.z};
        for (const ShapePart& p : b.parts) {
            key.insert(key.end(), {double(static_cast<int>(p.kind)), p.position.x, p.position.y, p.position.z, p.orientation.w,
                                   p.orientation.x, p.orientation.y, p.orientation.z, p.half.x, p.half.y, p.half.z});
            for (const V3& v : p.points) key.insert(key.end(), {v.x, v.y, v.z});
        }
        auto& shape = shapeCache_[key];
        if (shape != nullptr) return shape;
        if (!b.parts.empty()) {
            auto compound = std::make_unique<btCompoundShape>();
            for (const ShapePart& p : b.parts) {
                compound->addChildShape(btTransform(quat(p.orientation), bt(p.position)), partShape(p));
            }
            shape = addShape(std::move(compound));
        } else if (b.kind == BodySpec::Kind::Sphere) {
            shape = addShape(std::make_unique<btSphereShape>(static_cast<btScalar>(b.half.x)));
        } else if (b.kind == BodySpec::Kind::Hull) {
            ShapePart p;
            p.kind = ShapePart::Kind::Hull;
            p.points = scene_->hullPoints;
            shape = partShape(p);
        } else if (b.kind == BodySpec::Kind::Capsule) {
            shape = addShape(std::make_unique<btCapsuleShape>(static_cast<btScalar>(b.half.x), static_cast<btScalar>(2 * b.half.y)));
        } else {
            shape = addShape(std::make_unique<btBoxShape>(bt(b.half)));
        }
        return shape;
    }

    // Where the body's shape has its centre of mass in the spec's body frame (Bullet's body frame).
    btVector3 centerOffset(const BodySpec& b) const {
        return b.kind == BodySpec::Kind::SharedCompound && b.parts.empty() ? sharedCompoundCenter_ : btVector3(0, 0, 0);
    }

    static btQuaternion quat(Q q) {
        return {static_cast<btScalar>(q.x), static_cast<btScalar>(q.y), static_cast<btScalar>(q.z), static_cast<btScalar>(q.w)};
    }

    std::unique_ptr<btRigidBody> makeBody(const BodySpec& b) {
        btCollisionShape* shape = shapeFor(b);
        const bool moving = !b.isStatic && !b.isKinematic;
        const auto mass = static_cast<btScalar>(moving ? b.mass : 0.0);
        btVector3 inertia(0, 0, 0);
        if (mass > 0) shape->calculateLocalInertia(mass, inertia);
        // A body of parts: its origin is the body's origin here (Bullet takes the inertia about it: close enough for
        // a benchmark); the shared compound is shifted to its centre of mass (the trees topple about it).
        btTransform xf(quat(b.orientation), bt(b.position) + quatRotate(quat(b.orientation), centerOffset(b)));
        auto* state = new btDefaultMotionState(xf);  // owned by the body's slot: freed with it
        btRigidBody::btRigidBodyConstructionInfo info(mass, state, shape, inertia);
        // Bullet combines friction and restitution as products: each body gets sqrt(mu) for a pair value mu.
        info.m_friction = static_cast<btScalar>(std::sqrt(b.friction >= 0 ? b.friction : scene_->friction));
        // A body's own restitution as given; the scene's is a pair value (Bullet multiplies the two: sqrt each).
        info.m_restitution = static_cast<btScalar>(b.restitution >= 0 ? b.restitution : std::sqrt(scene_->restitution));
        auto body = std::make_unique<btRigidBody>(info);
        body->setLinearVelocity(bt(b.linearVelocity));
        body->setAngularVelocity(bt(b.angularVelocity));
        if (b.isKinematic) {
            body->setCollisionFlags(body->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
            body->setActivationState(DISABLE_DEACTIVATION);
        }
        if (!scene_->sleeping && mass > 0) body->setActivationState(DISABLE_DEACTIVATION);
        if (b.isBullet) {  // Bullet's continuous collision: a swept sphere inside the shape, above a motion threshold
            btVector3 centre;
            btScalar radius;
            shape->getBoundingSphere(centre, radius);
            body->setCcdMotionThreshold(static_cast<btScalar>(0.25) * radius);
            body->setCcdSweptSphereRadius(static_cast<btScalar>(0.5) * radius);
        }
        if (!scene_->bodyCollisions) {  // every body in filter group 2, masking group 2 out: nothing collides
            world_->addRigidBody(body.get(), 2, ~2);
        } else {
            world_->addRigidBody(body.get());
        }
        body->setUserIndex(b.filterGroup);
        states_.emplace_back(state);
        return body;
    }

    // A churn scene's ragdoll joint (frames in each body; Bullet's cone-twist
    // and hinge turn about their frames' x and z axes, Box3D's about z).
    btTypedConstraint* makeJoint(const JointSpec& j, btRigidBody* a, btRigidBody& b) {
        const btQuaternion zToX(btVector3(0, 1, 0), static_cast<btScalar>(-1.5707963267948966));  // maps x to z
        const btTransform frameB(quat(j.frameB), bt(j.localB));
        const btTransform frameA(quat(j.frameA), bt(j.localA));
        btTypedConstraint* c = nullptr;
        if (j.type == JointSpec::Type::Hinge) {
            auto* h = a != nullptr ? new btHingeConstraint(*a, b, frameA, frameB) : new btHingeConstraint(b, frameB);
            h->setLimit(static_cast<btScalar>(j.lower), static_cast<btScalar>(j.upper));
            h->enableAngularMotor(true, 0, static_cast<btScalar>(j.frictionTorque * scene_->dt));  // friction: a motor at rest
            c = h;
        } else if (j.type == JointSpec::Type::ConeTwist) {
            const btTransform fa(quat(j.frameA) * zToX, bt(j.localA)), fb(quat(j.frameB) * zToX, bt(j.localB));
            auto* t = a != nullptr ? new btConeTwistConstraint(*a, b, fa, fb) : new btConeTwistConstraint(b, fb);
            // Bullet's twist limit is symmetric: the span of Box3D's.
            t->setLimit(static_cast<btScalar>(j.swing), static_cast<btScalar>(j.swing), static_cast<btScalar>(0.5 * (j.upper - j.lower)));
            c = t;
        } else {
            c = a != nullptr ? static_cast<btTypedConstraint*>(new btPoint2PointConstraint(*a, b, bt(j.localA), bt(j.localB)))
                             : new btPoint2PointConstraint(b, bt(j.localB));
        }
        world_->addConstraint(c, /*disableCollisionsBetweenLinkedBodies=*/true);
        return c;
    }

    btCollisionShape* addShape(std::unique_ptr<btCollisionShape> s) {
        shapes_.push_back(std::move(s));
        return shapes_.back().get();
    }

    // A static btBvhTriangleMeshShape over a scene mesh (Bullet keeps pointers into the arrays).
    btCollisionShape* buildMesh(const MeshSpec& m) {
        meshArrays_.push_back(std::make_unique<MeshArrays>());
        MeshArrays& arrays = *meshArrays_.back();
        for (const V3& v : m.vertices) {
            arrays.vertices.push_back(static_cast<btScalar>(v.x));
            arrays.vertices.push_back(static_cast<btScalar>(v.y));
            arrays.vertices.push_back(static_cast<btScalar>(v.z));
        }
        for (const auto& t : m.triangles) {
            for (const std::uint32_t k : t) arrays.indices.push_back(static_cast<int>(k));
        }
        arrays.array = std::make_unique<btTriangleIndexVertexArray>(
            static_cast<int>(m.triangles.size()), arrays.indices.data(), 3 * static_cast<int>(sizeof(int)),
            static_cast<int>(m.vertices.size()), arrays.vertices.data(), 3 * static_cast<int>(sizeof(btScalar)));
        return addShape(std::make_unique<btBvhTriangleMeshShape>(arrays.array.get(), /*useQuantizedAabbCompression=*/true));
    }

    // A btCompoundShape of hulls, shifted so its centre of mass is the body's
    // frame (`center`: where that is in the spec's body frame). The children's
    // masses are in proportion to their points' bounding boxes' volumes: exact
    // ratios for the trees' prisms of one shape, and for a single child.
    btCompoundShape* buildCompound(const std::vector<std::vector<V3>>& parts, btVector3& center) {
        std::vector<btScalar> weights;
        btScalar total = 0;
        center.setZero();
        std::vector<btVector3> centroids;
        for (const std::vector<V3>& part : parts) {
            btVector3 lo = bt(part.front()), hi = lo, sum(0, 0, 0);
            for (const V3& p : part) {
                lo.setMin(bt(p));
                hi.setMax(bt(p));
                sum += bt(p);
            }
            const btVector3 size = hi - lo;
            weights.push_back(size.x() * size.y() * size.z());
            total += weights.back();
            centroids.push_back(sum / static_cast<btScalar>(part.size()));
            center += centroids.back() * weights.back();
        }
        center /= total;
        auto compound = std::make_unique<btCompoundShape>();
        for (const std::vector<V3>& part : parts) {
            auto h = std::make_unique<btConvexHullShape>();
            for (const V3& p : part) h->addPoint(bt(p) - center, false);
            h->recalcLocalAabb();
            h->optimizeConvexHull();
            compound->addChildShape(btTransform::getIdentity(), h.get());
            addShape(std::move(h));
        }
        btCompoundShape* out = compound.get();
        addShape(std::move(compound));
        return out;
    }

    void buildCloth(const ClothSpec& c) {
        auto* soft = static_cast<btSoftRigidDynamicsWorld*>(world_.get());
        btSoftBodyWorldInfo& info = soft->getWorldInfo();
        info.m_gravity = bt(scene_->gravity);
        info.m_sparsesdf.Initialize();
        const double half = 0.5 * c.spacing * (c.n - 1);
        const auto y = static_cast<btScalar>(c.height), h = static_cast<btScalar>(half);
        // Node (i, j) = j * n + i, i along x, j along z: the harness's numbering.
        cloth_ = btSoftBodyHelpers::CreatePatch(info, {-h, y, -h}, {h, y, -h}, {-h, y, h}, {h, y, h}, c.n, c.n, 0,
                                                /*gendiags=*/true);
        cloth_->generateBendingConstraints(2, cloth_->m_materials[0]);
        cloth_->setTotalMass(static_cast<btScalar>(c.particleMass * c.n * c.n));
        cloth_->getCollisionShape()->setMargin(btScalar(0.02));  // the particle radius Fulcrum uses
        soft->addSoftBody(cloth_);
    }

    const SceneSpec* scene_ = nullptr;
    std::unique_ptr<btCollisionConfiguration> config_;
    std::unique_ptr<btCollisionDispatcher> dispatcher_;
    std::unique_ptr<btBroadphaseInterface> broadphase_;
    std::unique_ptr<btSequentialImpulseConstraintSolver> solver_;
    std::unique_ptr<btDiscreteDynamicsWorld> world_;
    std::vector<std::unique_ptr<btCollisionShape>> shapes_;
    std::vector<std::unique_ptr<btDefaultMotionState>> states_;
    std::vector<btVector3> centerOffsets_;  // per scene body: its centre of mass in the spec's body frame
    std::vector<bool> onPath_;              // per scene body: moved by a kinematic path (moveKinematic)
    struct MeshArrays {
        std::vector<btScalar> vertices;
        std::vector<int> indices;
        std::unique_ptr<btTriangleIndexVertexArray> array;
    };
    std::vector<std::unique_ptr<MeshArrays>> meshArrays_;
    btCompoundShape* sharedCompound_ = nullptr;
    btVector3 sharedCompoundCenter_{0, 0, 0};
    std::vector<std::unique_ptr<btRigidBody>> bodies_;
    std::vector<btTypedConstraint*> constraints_;
    btSoftBody* cloth_ = nullptr;
    std::map<std::vector<double>, btCollisionShape*> shapeCache_;
    std::map<int, btCollisionShape*> meshShapes_;
    std::vector<std::unique_ptr<btRigidBody>> gridBodies_;
    std::vector<std::vector<std::unique_ptr<btRigidBody>>> groupBodies_;
    std::vector<std::vector<btTypedConstraint*>> groupJoints_;
    // Bodies sharing a negative filter group (the user index) never collide; the rest as Bullet's default.
    struct GroupFilter final : btOverlapFilterCallback {
        bool needBroadphaseCollision(btBroadphaseProxy* a, btBroadphaseProxy* b) const override {
            if ((a->m_collisionFilterGroup & b->m_collisionFilterMask) == 0 || (b->m_collisionFilterGroup & a->m_collisionFilterMask) == 0) {
                return false;
            }
            const int ga = static_cast<const btCollisionObject*>(a->m_clientObject)->getUserIndex();
            const int gb = static_cast<const btCollisionObject*>(b->m_clientObject)->getUserIndex();
            return !(ga < 0 && ga == gb);
        }
    } groupFilter_;
};

}  // namespace

std::unique_ptr<Engine> makeBullet() { return std::make_unique<BulletEngine>(); }

}  // namespace bench
