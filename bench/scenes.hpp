#pragma once
// The benchmark scenes of docs/benchmark-scenes.md as engine-neutral lists of
// boxes and spheres, so Fulcrum and the peer engines build exactly the same
// thing. Header-only: bench/CMakeLists.txt makes an executable of every .cpp.
#include <cmath>
#include <string>
#include <vector>

namespace bench {

struct BodySpec {
    enum class Kind { Box, Sphere } kind = Kind::Box;
    float x = 0, y = 0, z = 0;
    float hx = 0.5f, hy = 0.5f, hz = 0.5f;  // box half extents; sphere radius in hx
    bool isStatic = false;
    float mass = 1;
};

struct SceneSpec {
    std::string name;
    std::vector<BodySpec> bodies;
    int steps = 600;
    float dt = 1.0f / 60;
    float friction = 0.6f;     // effective pair coefficient
    bool sleeping = true;
    bool pyramid = false;      // quality = drift and top sink
    int topIndex = -1;         // the top box of a pyramid
};

inline void addGround(SceneSpec& s, float half) {
    BodySpec g;
    g.isStatic = true;
    g.hx = half;
    g.hy = 0.5f;
    g.hz = half;
    g.y = -0.5f;
    s.bodies.push_back(g);
}

inline SceneSpec pyramid(const std::string& name, int base, int steps) {
    SceneSpec s;
    s.name = name;
    s.steps = steps;
    s.sleeping = false;  // a sleeping pyramid costs nothing: measure the solver
    s.pyramid = true;
    addGround(s, 50);
    for (int row = 0; row < base; ++row) {
        const int count = base - row;
        for (int i = 0; i < count; ++i) {
            BodySpec b;
            b.x = static_cast<float>(i) - 0.5f * static_cast<float>(count - 1);
            b.y = 0.5f + static_cast<float>(row);
            s.bodies.push_back(b);
        }
    }
    s.topIndex = static_cast<int>(s.bodies.size()) - 1;
    return s;
}

// Floor 40 x 40 m (top at y = 0) inside four static walls 10 m tall, inner size 32 x 32 m.
inline void addArena(SceneSpec& s) {
    addGround(s, 20);
    const float inner = 16, t = 0.5f, hh = 5;
    const float xs[4] = {inner + t, -(inner + t), 0, 0};
    const float zs[4] = {0, 0, inner + t, -(inner + t)};
    for (int i = 0; i < 4; ++i) {
        BodySpec w;
        w.isStatic = true;
        w.x = xs[i];
        w.z = zs[i];
        w.y = hh;
        w.hy = hh;
        w.hx = i < 2 ? t : inner + 2 * t;
        w.hz = i < 2 ? inner + 2 * t : t;
        s.bodies.push_back(w);
    }
}

// nx x ny x nz grid spaced `spacing`, lowest layer at y = 2, layer k shifted by
// ((k mod 2) 0.25, 0, (floor(k/2) mod 2) 0.25) so columns don't line up.
inline SceneSpec pile(const std::string& name, BodySpec::Kind kind, int nx, int ny, int nz, float spacing, int steps) {
    SceneSpec s;
    s.name = name;
    s.steps = steps;
    addArena(s);
    for (int k = 0; k < ny; ++k) {
        const float sx = static_cast<float>(k % 2) * 0.25f, sz = static_cast<float>((k / 2) % 2) * 0.25f;
        for (int i = 0; i < nx; ++i) {
            for (int j = 0; j < nz; ++j) {
                BodySpec b;
                b.kind = kind;
                if (kind == BodySpec::Kind::Sphere) b.hx = b.hy = b.hz = 0.5f;
                b.x = (static_cast<float>(i) - 0.5f * static_cast<float>(nx - 1)) * spacing + sx;
                b.z = (static_cast<float>(j) - 0.5f * static_cast<float>(nz - 1)) * spacing + sz;
                b.y = 2 + static_cast<float>(k) * spacing;
                s.bodies.push_back(b);
            }
        }
    }
    return s;
}

inline std::vector<SceneSpec> allScenes(bool quick) {
    std::vector<SceneSpec> scenes;
    if (quick) {
        scenes.push_back(pyramid("pyramid20", 20, 120));
        scenes.push_back(pyramid("pyramid_large(30)", 30, 120));
        scenes.push_back(pile("box_pile(500)", BodySpec::Kind::Box, 10, 5, 10, 1.5f, 120));
        scenes.push_back(pile("sphere_pile(1000)", BodySpec::Kind::Sphere, 10, 10, 10, 1.2f, 120));
    } else {
        scenes.push_back(pyramid("pyramid20", 20, 600));
        scenes.push_back(pyramid("pyramid_large", 60, 600));
        scenes.push_back(pile("box_pile", BodySpec::Kind::Box, 20, 10, 20, 1.5f, 600));
        scenes.push_back(pile("sphere_pile", BodySpec::Kind::Sphere, 25, 16, 25, 1.2f, 600));
    }
    return scenes;
}

// What every engine reports for a scene.
struct RunResult {
    bool ran = false;
    std::vector<double> stepMs;
    double drift = 0;        // pyramids: worst horizontal drift (m)
    double sink = 0;         // pyramids: top box sink (m)
    int asleep = 0;          // bodies asleep at the end
    double penetration = 0;  // deepest penetration at the end (m)
};

}  // namespace bench
