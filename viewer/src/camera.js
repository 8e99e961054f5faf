// The replay page's camera choice: free orbit (the default), or following a
// vehicle, a character or any moving body, chosen in a drop-down that this
// module adds to the controls bar. Following keeps the orbit controls: the
// point they orbit glides after the followed body (an exponential approach,
// so the view never jerks) and the camera moves with it, keeping the distance
// and direction the user set; behind a vehicle the view also turns with the
// chassis's heading, a chase camera. A jump of the body (a seek on the
// timeline, the loop starting over) is followed at once, not glided across.
import { Quaternion, Vector3 } from 'three';

const followRate = 5;  // 1/s: the glide closes 1 - e^(-5 dt) of the gap per frame

// bodies: the viewer's body entries ({ rec, group, extent }); vehicles and
// characters: [{ name, body }] (body indices).
export function createCameraChoice({ camera, controls, bodies, vehicles, characters }) {
  const choices = [{ label: 'free orbit', body: -1 }];
  for (const v of vehicles) choices.push({ label: `vehicle: ${v.name}`, body: v.body, vehicle: true });
  for (const c of characters) choices.push({ label: `character: ${c.name}`, body: c.body });
  const taken = new Set(choices.map((c) => c.body));
  bodies.forEach((b, index) => {
    if (b.rec.type === 'dynamic' && !taken.has(index) && choices.length < 200) choices.push({ label: `body: ${b.rec.name}`, body: index });
  });

  const select = document.createElement('select');
  select.id = 'camera';
  select.setAttribute('aria-label', 'camera');
  choices.forEach((c, i) => select.add(new Option(c.label, String(i))));
  const label = document.createElement('label');
  label.append('camera ', select);
  document.getElementById('controls')?.append(label);

  let chosen = choices[0];
  const heading = new Vector3(), lastHeading = new Vector3(), turn = new Quaternion(), step = new Vector3();
  const lastPosition = new Vector3();
  // The world's up is the camera's (y, or z for a z-up recording: viewer.js).
  const forward = new Vector3(0, 0, 1), up = camera.up.clone();
  const level = (v) => v.addScaledVector(up, -v.dot(up));  // the part of v across up

  function headingOf(body, out) {
    level(out.copy(forward).applyQuaternion(body.group.quaternion));
    return out.lengthSq() > 1e-8 ? out.normalize() : out.set(0, 0, 1);
  }

  function choose(index) {
    chosen = choices[index] ?? choices[0];
    select.value = String(choices.indexOf(chosen));
    if (chosen.body < 0) return;
    const body = bodies[chosen.body];
    // Start from behind and above the body (its heading for a vehicle), far
    // enough to see it and its surroundings.
    const distance = Math.max(6, 5 * body.extent);
    const back = chosen.vehicle ? headingOf(body, heading).clone().negate() : level(camera.position.clone().sub(controls.target)).normalize();
    if (back.lengthSq() < 1e-8) back.set(0, 0, 1);
    controls.target.copy(body.group.position);
    camera.position.copy(body.group.position).addScaledVector(back, distance * 0.9).addScaledVector(up, distance * 0.45);
    headingOf(body, lastHeading);
    lastPosition.copy(body.group.position);
    controls.update();
  }
  select.addEventListener('change', () => choose(Number(select.value)));

  // Called every rendered frame with the real time since the last one.
  function update(dt) {
    if (chosen.body < 0) return;
    const body = bodies[chosen.body];
    if (chosen.vehicle) {
      // Turn the view about the target by the heading's change (yaw only).
      headingOf(body, heading);
      turn.setFromUnitVectors(lastHeading, heading);
      lastHeading.copy(heading);
      const offset = camera.position.clone().sub(controls.target).applyQuaternion(turn);
      camera.position.copy(controls.target).add(offset);
    }
    // Further in one frame than 3 m or twice its size: a jump, not motion.
    const jumped = body.group.position.distanceTo(lastPosition) > Math.max(3, 2 * body.extent);
    lastPosition.copy(body.group.position);
    const u = jumped ? 1 : 1 - Math.exp(-followRate * Math.max(dt, 0));
    step.copy(body.group.position).sub(controls.target).multiplyScalar(u);
    controls.target.add(step);
    camera.position.add(step);
  }

  return {
    update,
    choose,
    get choice() { return chosen.label; },
    get choices() { return choices.map((c) => c.label); },
    get following() { return chosen.body >= 0; },
  };
}
