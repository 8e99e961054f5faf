// Vehicles' wheels on the replay page: each wheel a tyre with a hub and
// spokes (so its spin shows), a child of its chassis body's group placed
// every frame from the recorded suspension length, steering angle and spin
// (docs/recording.md, "vehicles"). Old recordings have no "vehicles": nothing
// is drawn.
import { BoxGeometry, CylinderGeometry, Group, Mesh, MeshStandardMaterial, Vector3 } from 'three';

// rec: the decoded recording; bodies: the viewer's body entries ({ group }).
export function createVehicles(rec, bodies, srgb) {
  const frameCount = rec.frames;
  const tyre = new MeshStandardMaterial({ color: srgb([0.08, 0.08, 0.09]), roughness: 0.9 });
  const hub = new MeshStandardMaterial({ color: srgb([0.78, 0.8, 0.84]), roughness: 0.35, metalness: 0.6 });
  const vehicles = (rec.vehicles ?? []).filter((v) => bodies[v.chassis]).map((vehicle) => {
    const chassis = bodies[vehicle.chassis].group;
    const wheels = vehicle.wheels.map((wheel, index) => {
      // steer: about the chassis's up at the wheel centre; spin: about the axle (x).
      const steer = new Group(), spin = new Group();
      steer.name = `${vehicle.name} wheel ${index}`;
      const r = wheel.radius, w = wheel.width;
      const body = new Mesh(new CylinderGeometry(r, r, w, 28).rotateZ(Math.PI / 2), tyre);
      const rim = new Mesh(new CylinderGeometry(r * 0.62, r * 0.62, w * 1.04, 20).rotateZ(Math.PI / 2), hub);
      const spokeA = new Mesh(new BoxGeometry(w * 1.1, r * 1.5, r * 0.18), hub);
      const spokeB = new Mesh(new BoxGeometry(w * 1.1, r * 0.18, r * 1.5), tyre);
      for (const m of [body, rim, spokeA, spokeB]) { m.castShadow = true; m.receiveShadow = true; spin.add(m); }
      steer.add(spin);
      chassis.add(steer);
      return { rec: wheel, steer, spin };
    });
    return { rec: vehicle, wheels, poses: vehicle.poses };
  });

  // Places every wheel for frame + alpha (the same interpolation as the bodies').
  function update(frame, alpha) {
    for (const vehicle of vehicles) {
      const n = vehicle.wheels.length, p = vehicle.poses;
      const a = frame * n * 3, b = alpha > 0 && frame + 1 < frameCount ? a + n * 3 : a;
      vehicle.wheels.forEach((wheel, i) => {
        const k = 3 * i;
        const at = (c) => p[a + k + c] + (p[b + k + c] - p[a + k + c]) * alpha;
        const m = wheel.rec.mount;
        wheel.steer.position.set(m[0], m[1] - at(0), m[2]);
        wheel.steer.rotation.set(0, at(1), 0);
        wheel.spin.rotation.set(at(2), 0, 0);
        wheel.steer.updateMatrixWorld();
      });
    }
  }

  return {
    update,
    // For the camera choice and the browser test.
    list: vehicles.map((v) => ({ name: v.rec.name, body: v.rec.chassis })),
    wheelCount: vehicles.reduce((n, v) => n + v.wheels.length, 0),
    // Every wheel's steering and spin angle and world position as drawn now.
    wheels() {
      return vehicles.flatMap((v) => v.wheels.map((w) => ({
        vehicle: v.rec.name, steer: w.steer.rotation.y, spin: w.spin.rotation.x,
        position: w.steer.getWorldPosition(new Vector3()).toArray(),
      })));
    },
  };
}
