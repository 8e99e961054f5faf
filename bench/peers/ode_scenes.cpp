// ODE 0.16 (Debian's libode-dev, double precision) running bench/scenes.hpp at
// its defaults: dWorldQuickStep (20 iterations, SOR 1.3), ERP 0.2, CFM 1e-5,
// a dHashSpace, up to 4 contact points per colliding pair with the friction
// pyramid approximation (dContactApprox1, so mu is a coefficient, not a force
// limit), auto-disable (ODE's sleeping) at its default thresholds when the
// scene has sleeping on. ODE has no cloth or particle system: the cloth scene
// is reported as not held.
#include <ode/ode.h>

#include <algorithm>
#include <cmath>
#include <mutex>

#include "peers.hpp"

namespace bench {
namespace {

constexpr int kMaxContacts = 4;

class OdeEngine final : public Engine {
public:
    OdeEngine() {
        static std::once_flag once;
        std::call_once(once, [] { dInitODE2(0); });
    }
    ~OdeEngine() override {
        if (contacts_ != nullptr) dJointGroupDestroy(contacts_);
        if (space_ != nullptr) dSpaceDestroy(space_);  // destroys its geoms
        if (world_ != nullptr) dWorldDestroy(world_);  // destroys bodies and joints
    }

    std::string name() const override { return "ODE"; }
    std::string settings() const override {
        return "ODE 0.16 (double): dWorldQuickStep, 20 iterations, SOR 1.3, ERP 0.2, CFM 1e-5, dHashSpace, <= 4 "
               "contacts per pair, dContactApprox1 friction pyramid with the pair mu, bounce 0; auto-disable on "
               "(default thresholds) where the scene sleeps; no cloth";
    }

    bool build(const SceneSpec& scene, std::string& why) override {
        if (!scene.hullPoints.empty() || !scene.bodyCollisions || scene.substeps > 0) {
            why = "Box3D's suite is run in Fulcrum and Bullet only";
            return false;
        }
        if (scene.cloth.n > 0) {
            why = "ODE has no cloth or particle system";
            return false;
        }
        scene_ = &scene;
        world_ = dWorldCreate();
        space_ = dHashSpaceCreate(nullptr);
        contacts_ = dJointGroupCreate(0);
        dWorldSetGravity(world_, scene.gravity.x, scene.gravity.y, scene.gravity.z);
        dWorldSetAutoDisableFlag(world_, scene.sleeping ? 1 : 0);
        for (const BodySpec& b : scene.bodies) {
            dGeomID geom = nullptr;
            dMass mass;
            if (b.kind == BodySpec::Kind::Sphere) {
                geom = dCreateSphere(space_, b.half.x);
                dMassSetSphereTotal(&mass, b.mass, b.half.x);
            } else if (b.kind == BodySpec::Kind::Capsule) {
                geom = dCreateCapsule(space_, b.half.x, 2 * b.half.y);   // along the geom's z
                dMassSetCapsuleTotal(&mass, b.mass, 2, b.half.x, 2 * b.half.y);  // along the body's y
            } else {
                geom = dCreateBox(space_, 2 * b.half.x, 2 * b.half.y, 2 * b.half.z);
                dMassSetBoxTotal(&mass, b.mass, 2 * b.half.x, 2 * b.half.y, 2 * b.half.z);
            }
            const dQuaternion q = {b.orientation.w, b.orientation.x, b.orientation.y, b.orientation.z};
            if (b.isStatic) {
                dGeomSetPosition(geom, b.position.x, b.position.y, b.position.z);
                dGeomSetQuaternion(geom, q);
                bodies_.push_back(nullptr);
                continue;
            }
            dBodyID body = dBodyCreate(world_);
            dBodySetMass(body, &mass);
            dBodySetPosition(body, b.position.x, b.position.y, b.position.z);
            dBodySetQuaternion(body, q);
            dBodySetLinearVel(body, b.linearVelocity.x, b.linearVelocity.y, b.linearVelocity.z);
            dBodySetAngularVel(body, b.angularVelocity.x, b.angularVelocity.y, b.angularVelocity.z);
            dGeomSetBody(geom, body);
            if (b.kind == BodySpec::Kind::Capsule) {  // turn the geom's z axis onto the body's y
                dMatrix3 r;
                dRFromAxisAndAngle(r, 1, 0, 0, -1.5707963267948966);
                dGeomSetOffsetRotation(geom, r);
            }
            bodies_.push_back(body);
        }
        for (const JointSpec& j : scene.joints) {
            dJointID joint = dJointCreateBall(world_, nullptr);
            dJointAttach(joint, bodies_[static_cast<std::size_t>(j.b)], j.a < 0 ? nullptr : bodies_[static_cast<std::size_t>(j.a)]);
            dJointSetBallAnchor(joint, j.anchor.x, j.anchor.y, j.anchor.z);
        }
        return true;
    }

    void step() override {
        deepest_ = 0;
        dSpaceCollide(space_, this, &OdeEngine::nearCallback);
        dWorldQuickStep(world_, scene_->dt);
        dJointGroupEmpty(contacts_);
    }

    BodyState body(std::size_t i) const override {
        dBodyID b = bodies_[i];
        if (b == nullptr) {
            const BodySpec& s = scene_->bodies[i];
            return {s.position, s.orientation, {}, {}};
        }
        const dReal* p = dBodyGetPosition(b);
        const dReal* q = dBodyGetQuaternion(b);
        const dReal* v = dBodyGetLinearVel(b);
        const dReal* w = dBodyGetAngularVel(b);
        return {{p[0], p[1], p[2]}, {q[0], q[1], q[2], q[3]}, {v[0], v[1], v[2]}, {w[0], w[1], w[2]}};
    }
    bool asleep(std::size_t i) const override { return bodies_[i] != nullptr && dBodyIsEnabled(bodies_[i]) == 0; }
    double deepestPenetration() const override { return deepest_; }

private:
    static void nearCallback(void* data, dGeomID a, dGeomID b) {
        auto* self = static_cast<OdeEngine*>(data);
        dBodyID ba = dGeomGetBody(a), bb = dGeomGetBody(b);
        if (ba == nullptr && bb == nullptr) return;
        if (ba != nullptr && bb != nullptr && dAreConnectedExcluding(ba, bb, dJointTypeContact)) return;
        dContact contact[kMaxContacts];
        const int n = dCollide(a, b, kMaxContacts, &contact[0].geom, sizeof(dContact));
        for (int i = 0; i < n; ++i) {
            contact[i].surface.mode = dContactApprox1;
            contact[i].surface.mu = self->scene_->friction;
            contact[i].surface.bounce = 0;
            self->deepest_ = std::max(self->deepest_, static_cast<double>(contact[i].geom.depth));
            dJointID j = dJointCreateContact(self->world_, self->contacts_, &contact[i]);
            dJointAttach(j, ba, bb);
        }
    }

    const SceneSpec* scene_ = nullptr;
    dWorldID world_ = nullptr;
    dSpaceID space_ = nullptr;
    dJointGroupID contacts_ = nullptr;
    std::vector<dBodyID> bodies_;
    double deepest_ = 0;
};

}  // namespace

std::unique_ptr<Engine> makeOde() { return std::make_unique<OdeEngine>(); }

}  // namespace bench
