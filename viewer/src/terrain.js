// Heightfields drawn as terrain on the replay page: grass, darker in the
// hollows and lighter and drier towards the tops (by each vertex's height
// within the field), so low relief reads as relief even under flat light.
// Other static bodies keep their grey.
import { BufferAttribute, Color, MeshStandardMaterial, SRGBColorSpace } from 'three';

const low = new Color().setRGB(0.23, 0.36, 0.17, SRGBColorSpace);
const high = new Color().setRGB(0.55, 0.56, 0.33, SRGBColorSpace);

// bodies: the viewer's body entries ({ rec, meshes, awakeMaterial, sleepMaterial }).
export function paintTerrain(bodies) {
  for (const body of bodies) {
    if (body.rec.shape !== 'heightfield') continue;
    const material = new MeshStandardMaterial({ vertexColors: true, roughness: 0.95, metalness: 0 });
    for (const mesh of body.meshes) {
      const p = mesh.geometry.attributes.position;
      let lo = Infinity, hi = -Infinity;
      for (let k = 0; k < p.count; k++) { lo = Math.min(lo, p.getY(k)); hi = Math.max(hi, p.getY(k)); }
      const colours = new Float32Array(p.count * 3), c = new Color();
      for (let k = 0; k < p.count; k++) {
        c.lerpColors(low, high, hi > lo ? (p.getY(k) - lo) / (hi - lo) : 0).toArray(colours, 3 * k);
      }
      mesh.geometry.setAttribute('color', new BufferAttribute(colours, 3));
      mesh.material = material;
    }
    body.awakeMaterial = body.meshes.map(() => material);
    body.sleepMaterial = body.meshes.map(() => material);
  }
}
