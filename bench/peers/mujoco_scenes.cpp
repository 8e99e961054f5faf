// MuJoCo 2.2 (Debian's libmujoco-dev, double precision) running
// bench/scenes.hpp at its defaults: Euler integrator, Newton solver (100
// iterations, tolerance 1e-8), pyramidal friction cone, condim 3, soft
// constraints at solref (0.02, 1) / solimp defaults, no sleeping (MuJoCo has
// none). The model is MJCF generated here and loaded from a virtual file.
//
// Every body is free (a free joint) and a ball-and-socket joint is a `connect`
// equality constraint (MuJoCo's soft constraint at its default solref/solimp),
// with a contact exclusion between the two bodies. MuJoCo's other way, a
// kinematic tree with ball joints (joint error 0 by construction), cannot hold
// the chain: 2.2's XML parser refuses elements nested 100 deep.
//
// MuJoCo 2.2 reserves its constraint arrays for the worst case when the model
// is compiled: `njmax` rows of a dense njmax x njmax matrix (efc_AR, 12 bytes
// per entry with its sparse index) and njmax x nv Jacobians. Scenes whose
// worst case (12 contacts per dynamic body, 4 rows per contact) would need more
// than kMemoryBudget are reported as not held.
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <sstream>

#include "peers.hpp"

namespace bench {
namespace {

constexpr double kMemoryBudget = 3e9;  // bytes for the worst-case constraint arrays

class MujocoEngine final : public Engine {
public:
    ~MujocoEngine() override {
        if (data_ != nullptr) mj_deleteData(data_);
        if (model_ != nullptr) mj_deleteModel(model_);
    }

    std::string name() const override { return "MuJoCo"; }
    std::string settings() const override {
        return "MuJoCo 2.2.2 (double): Euler integrator, Newton solver (100 iterations, tolerance 1e-8), pyramidal "
               "cone, condim 3, default solref/solimp, geom friction = the pair mu (MuJoCo takes the max); ball joints as "
               "`connect` equality constraints between free bodies (a 100-deep kinematic tree exceeds 2.2's XML nesting limit); nconmax = 12 per dynamic body, njmax = 4 per contact; "
               "no sleeping; no particle cloth in 2.2's API (its composite cloth is a tree of bodies), not run";
    }

    bool build(const SceneSpec& scene, std::string& why) override {
        if (!scene.hullPoints.empty() || !scene.bodyCollisions || scene.substeps > 0) {
            why = "Box3D's suite is run in Fulcrum and Bullet only";
            return false;
        }
        if (scene.cloth.n > 0) {
            why = "MuJoCo 2.2 has no particle cloth (its <composite type=\"cloth\"> is a tree of rigid bodies, not run)";
            return false;
        }
        scene_ = &scene;
        // Warnings (e.g. contact overflow) are counted in mjData and reported by note();
        // MuJoCo's default handler would also append them to MUJOCO_LOG.TXT in the working directory.
        mju_user_warning = [](const char*) {};
        const std::size_t n = scene.bodies.size();
        std::size_t dynamic = 0;
        for (const BodySpec& b : scene.bodies) dynamic += b.isStatic ? 0 : 1;
        const double nconmax = 12.0 * static_cast<double>(dynamic) + 100;
        const double njmax = 4 * nconmax + 3.0 * static_cast<double>(scene.joints.size());
        const double nv = 6.0 * static_cast<double>(dynamic);
        const double bytes = 12 * njmax * njmax + 2 * 12 * njmax * nv;
        if (bytes > kMemoryBudget) {
            char text[200];
            std::snprintf(text, sizeof text, "worst-case constraint arrays need %.0f GB (njmax %.0f); budget %.0f GB",
                          bytes / 1e9, njmax, kMemoryBudget / 1e9);
            why = text;
            return false;
        }

        std::ostringstream xml;
        xml.precision(10);
        xml << "<mujoco model=\"bench\">\n<option timestep=\"" << scene.dt << "\" gravity=\"" << scene.gravity.x << ' '
            << scene.gravity.y << ' ' << scene.gravity.z << "\"/>\n"
            << "<size nconmax=\"" << static_cast<long>(nconmax) << "\" njmax=\"" << static_cast<long>(njmax) << "\"/>\n"
            << "<default><geom friction=\"" << scene.friction << " 0.005 0.0001\"/></default>\n<worldbody>\n";
        for (std::size_t i = 0; i < n; ++i) {
            const BodySpec& b = scene.bodies[i];
            if (b.isStatic) {
                xml << "<geom";
                writeGeom(xml, b, true);
                xml << "/>\n";
            }
        }
        for (std::size_t i = 0; i < n; ++i) {
            const BodySpec& b = scene.bodies[i];
            if (b.isStatic) continue;
            xml << "<body name=\"b" << i << '"';
            writeVec(xml, "pos", b.position);
            writeQuat(xml, b.orientation);
            xml << "><freejoint/><geom";
            writeGeom(xml, b, false);
            xml << "/></body>\n";
        }
        xml << "</worldbody>\n";
        if (!scene.joints.empty()) {
            // connect: anchor in body1's frame; body2 = world when the joint's other side is the world.
            xml << "<contact>\n";
            for (const JointSpec& j : scene.joints) {
                if (j.a >= 0) xml << "<exclude body1=\"b" << j.a << "\" body2=\"b" << j.b << "\"/>\n";
            }
            xml << "</contact>\n<equality>\n";
            for (const JointSpec& j : scene.joints) {
                const BodySpec& b = scene.bodies[static_cast<std::size_t>(j.b)];
                xml << "<connect body1=\"b" << j.b << "\" body2=\"";
                if (j.a < 0) {
                    xml << "world\"";
                } else {
                    xml << 'b' << j.a << '"';
                }
                writeVec(xml, "anchor", rotate(conjugate(b.orientation), j.anchor - b.position));
                xml << "/>\n";
            }
            xml << "</equality>\n";
        }
        xml << "</mujoco>\n";

        const std::string text = xml.str();
        mjVFS vfs;
        mj_defaultVFS(&vfs);
        mj_makeEmptyFileVFS(&vfs, "bench.xml", static_cast<int>(text.size()));
        std::memcpy(vfs.filedata[mj_findFileVFS(&vfs, "bench.xml")], text.data(), text.size());
        char error[1000] = "";
        model_ = mj_loadXML("bench.xml", &vfs, error, sizeof error);
        mj_deleteVFS(&vfs);
        if (model_ == nullptr) {
            why = std::string("MJCF did not load: ") + error;
            return false;
        }
        data_ = mj_makeData(model_);
        if (data_ == nullptr) {
            why = "mj_makeData failed (out of memory)";
            return false;
        }
        ids_.assign(n, -1);
        for (std::size_t i = 0; i < n; ++i) {
            if (scene.bodies[i].isStatic) continue;
            char name[32];
            std::snprintf(name, sizeof name, "b%zu", i);
            ids_[i] = mj_name2id(model_, mjOBJ_BODY, name);
            // Free joint: linear velocity in world axes, angular velocity in body axes.
            const BodySpec& b = scene.bodies[i];
            const int dof = model_->jnt_dofadr[model_->body_jntadr[ids_[i]]];
            const V3 w = rotate(conjugate(b.orientation), b.angularVelocity);
            const double v[6] = {b.linearVelocity.x, b.linearVelocity.y, b.linearVelocity.z, w.x, w.y, w.z};
            std::copy(v, v + 6, data_->qvel + dof);
        }
        mj_forward(model_, data_);
        return true;
    }

    void step() override { mj_step(model_, data_); }
    void sync() override { mj_forward(model_, data_); }

    BodyState body(std::size_t i) const override {
        const BodySpec& s = scene_->bodies[i];
        if (s.isStatic) return {s.position, s.orientation, {}, {}};
        const int id = ids_[i];
        const mjtNum* p = data_->xpos + 3 * id;
        const mjtNum* q = data_->xquat + 4 * id;
        mjtNum vel[6];
        mj_objectVelocity(model_, data_, mjOBJ_BODY, id, vel, 0);  // (angular, linear), world axes
        return {{p[0], p[1], p[2]}, {q[0], q[1], q[2], q[3]}, {vel[3], vel[4], vel[5]}, {vel[0], vel[1], vel[2]}};
    }
    bool asleep(std::size_t) const override { return false; }
    double deepestPenetration() const override {
        double deepest = 0;
        for (int c = 0; c < data_->ncon; ++c) deepest = std::max(deepest, -static_cast<double>(data_->contact[c].dist));
        return deepest;
    }
    std::string note() const override {
        return data_ != nullptr && data_->warning[mjWARN_CONTACTFULL].number > 0 ? "nconmax overflow" : "";
    }

private:
    static void writeVec(std::ostringstream& xml, const char* name, V3 v) {
        xml << ' ' << name << "=\"" << v.x << ' ' << v.y << ' ' << v.z << '"';
    }
    static void writeQuat(std::ostringstream& xml, Q q) {
        xml << " quat=\"" << q.w << ' ' << q.x << ' ' << q.y << ' ' << q.z << '"';
    }
    // The geom in its body's frame (static geoms: in the world frame).
    static void writeGeom(std::ostringstream& xml, const BodySpec& b, bool world) {
        if (world) {
            writeVec(xml, "pos", b.position);
            writeQuat(xml, b.orientation);
        }
        switch (b.kind) {
            case BodySpec::Kind::Sphere: xml << " type=\"sphere\" size=\"" << b.half.x << '"'; break;
            case BodySpec::Kind::Capsule:
                // MuJoCo's capsule runs along z; ours along y: turn z onto y.
                xml << " type=\"capsule\" size=\"" << b.half.x << ' ' << b.half.y << "\" quat=\"0.7071067811865476 -0.7071067811865476 0 0\"";
                break;
            case BodySpec::Kind::Box: writeVec(xml, "size", b.half); xml << " type=\"box\""; break;
            case BodySpec::Kind::Hull:
            case BodySpec::Kind::SharedCompound: break;  // refused in build()
        }
        if (!b.isStatic) xml << " mass=\"" << b.mass << '"';
    }

    const SceneSpec* scene_ = nullptr;
    mjModel* model_ = nullptr;
    mjData* data_ = nullptr;
    std::vector<int> ids_;
};

}  // namespace

std::unique_ptr<Engine> makeMujoco() { return std::make_unique<MujocoEngine>(); }

}  // namespace bench
