// The lip aperture as three.js draws it, for the HUD and the browser tests:
// consumer.c's lip pair, found from the mesh's own jaw-opening target (jawOpen,
// or viseme_aa on a head with Oculus visemes only): the midline pair nearest
// at rest of a vertex that target carries and one it leaves.
import * as THREE from 'three';

function openingTarget(mesh) {
  const d = mesh.morphTargetDictionary;
  return d.jawOpen ?? d.viseme_aa ?? Object.entries(d).find(([name]) => /jawopen|viseme_aa$/i.test(name))?.[1];
}

/** [upper, lower] vertex indices of `mesh`, or null when it has no jaw-opening target. */
export function findLips(mesh) {
  const jaw = openingTarget(mesh);
  if (jaw === undefined) return null;
  const base = mesh.geometry.attributes.position, delta = mesh.geometry.morphAttributes.position[jaw];
  mesh.geometry.computeBoundingBox();
  const limit = 0.01 * mesh.geometry.boundingBox.getSize(new THREE.Vector3()).length();
  let most = 0;
  for (let i = 0; i < base.count; ++i) most = Math.max(most, Math.hypot(delta.getX(i), delta.getY(i), delta.getZ(i)));
  const lower = [], upper = [];
  for (let i = 0; i < base.count; ++i) {
    if (Math.abs(base.getX(i)) > limit) continue;
    const moved = Math.hypot(delta.getX(i), delta.getY(i), delta.getZ(i));
    if (moved >= 0.5 * most) lower.push(i); else if (moved <= 0.1 * most) upper.push(i);
  }
  let best = Infinity, lips = null;
  for (const i of lower) for (const j of upper) {
    const d = (base.getX(i) - base.getX(j)) ** 2 + (base.getY(i) - base.getY(j)) ** 2 + (base.getZ(i) - base.getZ(j)) ** 2;
    if (d < best) { best = d; lips = [j, i]; }
  }
  return lips;
}

// A vertex as three.js deforms it: base + sum of influence * relative morph delta.
function morphed(mesh, vertex) {
  const base = mesh.geometry.attributes.position, targets = mesh.geometry.morphAttributes.position;
  const p = [base.getX(vertex), base.getY(vertex), base.getZ(vertex)];
  mesh.morphTargetInfluences.forEach((w, k) => {
    if (w !== 0) { p[0] += w * targets[k].getX(vertex); p[1] += w * targets[k].getY(vertex); p[2] += w * targets[k].getZ(vertex); }
  });
  return p;
}

/** The distance between the lip pair in the mesh's current pose (its units). */
export function aperture(mesh, lips) {
  const [a, b] = [morphed(mesh, lips[0]), morphed(mesh, lips[1])];
  return Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}
