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
#include <memory>

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
        for (const auto& b : bodies_) world_->removeRigidBody(b.get());
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

        // Bullet combines friction as the product: each body gets sqrt(mu) for a pair value mu.
        const auto friction = static_cast<btScalar>(std::sqrt(scene.friction));
        btCollisionShape* unitBox = nullptr;
        btCollisionShape* unitSphere = nullptr;
        btCollisionShape* hull = nullptr;
        btCollisionShape* mesh = nullptr;
        btCompoundShape* compound = nullptr;
        btVector3 compoundCenter(0, 0, 0);  // the compound's centre of mass in the body frame
        for (const BodySpec& b : scene.bodies) {
            btCollisionShape* shape = nullptr;
            btVector3 centerOffset(0, 0, 0);
            if (b.kind == BodySpec::Kind::Mesh) {
                if (mesh == nullptr) mesh = buildMesh(*scene.mesh);
                shape = mesh;
            } else if (b.kind == BodySpec::Kind::Compound) {
                if (compound == nullptr) compound = buildCompound(scene.compoundHulls, compoundCenter);
                shape = compound;
                centerOffset = compoundCenter;
            } else if (b.kind == BodySpec::Kind::Sphere && b.half.x == 0.5 && !b.isStatic) {
                if (unitSphere == nullptr) unitSphere = addShape(std::make_unique<btSphereShape>(btScalar(0.5)));
                shape = unitSphere;
            } else if (b.kind == BodySpec::Kind::Sphere) {
                shape = addShape(std::make_unique<btSphereShape>(static_cast<btScalar>(b.half.x)));
            } else if (b.kind == BodySpec::Kind::Hull) {
                if (hull == nullptr) {
                    auto h = std::make_unique<btConvexHullShape>();
                    for (const V3& p : scene.hullPoints) h->addPoint(bt(p), false);
                    h->recalcLocalAabb();
                    h->optimizeConvexHull();
                    hull = addShape(std::move(h));
                }
                shape = hull;
            } else if (b.kind == BodySpec::Kind::Capsule) {
                shape = addShape(std::make_unique<btCapsuleShape>(static_cast<btScalar>(b.half.x), static_cast<btScalar>(2 * b.half.y)));
            } else if (!b.isStatic && b.half.x == 0.5 && b.half.y == 0.5 && b.half.z == 0.5) {
                if (unitBox == nullptr) unitBox = addShape(std::make_unique<btBoxShape>(btVector3(0.5f, 0.5f, 0.5f)));
                shape = unitBox;
            } else {
                shape = addShape(std::make_unique<btBoxShape>(bt(b.half)));
            }
            const auto mass = static_cast<btScalar>(b.isStatic || b.isKinematic ? 0.0 : b.mass);
            btVector3 inertia(0, 0, 0);
            if (mass > 0) shape->calculateLocalInertia(mass, inertia);
            const btQuaternion rotation(static_cast<btScalar>(b.orientation.x), static_cast<btScalar>(b.orientation.y),
                                        static_cast<btScalar>(b.orientation.z), static_cast<btScalar>(b.orientation.w));
            // Bullet's body frame is the centre of mass: a compound's children are shifted by it.
            btTransform xf(rotation, bt(b.position) + quatRotate(rotation, centerOffset));
            centerOffsets_.push_back(centerOffset);
            states_.push_back(std::make_unique<btDefaultMotionState>(xf));
            btRigidBody::btRigidBodyConstructionInfo info(mass, states_.back().get(), shape, inertia);
            info.m_friction = friction;
            info.m_restitution = static_cast<btScalar>(std::sqrt(scene.restitution));  // Bullet multiplies the two
            bodies_.push_back(std::make_unique<btRigidBody>(info));
            btRigidBody& body = *bodies_.back();
            if (b.isKinematic) {
                body.setCollisionFlags(body.getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
                body.setActivationState(DISABLE_DEACTIVATION);
            }
            body.setLinearVelocity(bt(b.linearVelocity));
            body.setAngularVelocity(bt(b.angularVelocity));
            if (!scene.sleeping && mass > 0) body.setActivationState(DISABLE_DEACTIVATION);
            if (scene.bodyCollisions) {
                world_->addRigidBody(&body);
            } else {  // every body in filter group 2, masking group 2 out: nothing collides
                world_->addRigidBody(&body, 2, ~2);
            }
        }
        for (const JointSpec& j : scene.joints) {
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

    void step() override { world_->stepSimulation(static_cast<btScalar>(scene_->dt), 0, static_cast<btScalar>(scene_->dt)); }

    void moveKinematic(std::size_t i, V3 origin, double) override {
        // Bullet turns the motion state's new transform into the kinematic body's velocity for the step.
        states_[i]->setWorldTransform(btTransform(btQuaternion::getIdentity(), bt(origin) + centerOffsets_[i]));
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
    btCollisionShape* addShape(std::unique_ptr<btCollisionShape> s) {
        shapes_.push_back(std::move(s));
        return shapes_.back().get();
    }

    // A static btBvhTriangleMeshShape over the scene's mesh (Bullet keeps pointers into the arrays).
    btCollisionShape* buildMesh(const MeshSpec& m) {
        for (const V3& v : m.vertices) {
            meshVertices_.push_back(static_cast<btScalar>(v.x));
            meshVertices_.push_back(static_cast<btScalar>(v.y));
            meshVertices_.push_back(static_cast<btScalar>(v.z));
        }
        for (const auto& t : m.triangles) {
            for (const std::uint32_t k : t) meshIndices_.push_back(static_cast<int>(k));
        }
        meshArray_ = std::make_unique<btTriangleIndexVertexArray>(
            static_cast<int>(m.triangles.size()), meshIndices_.data(), 3 * static_cast<int>(sizeof(int)),
            static_cast<int>(m.vertices.size()), meshVertices_.data(), 3 * static_cast<int>(sizeof(btScalar)));
        return addShape(std::make_unique<btBvhTriangleMeshShape>(meshArray_.get(), /*useQuantizedAabbCompression=*/true));
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
    std::vector<btVector3> centerOffsets_;  // per body: its centre of mass in the spec's body frame
    std::vector<btScalar> meshVertices_;
    std::vector<int> meshIndices_;
    std::unique_ptr<btTriangleIndexVertexArray> meshArray_;
    std::vector<std::unique_ptr<btRigidBody>> bodies_;
    std::vector<btTypedConstraint*> constraints_;
    btSoftBody* cloth_ = nullptr;
};

}  // namespace

std::unique_ptr<Engine> makeBullet() { return std::make_unique<BulletEngine>(); }

}  // namespace bench
