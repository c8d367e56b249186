// Heads for the browser tests, made from the built-in head's GLB by
// rewriting its JSON chunk (the binary chunk is kept as it is): only some of
// its morph targets (ARKit names only, Oculus visemes only, none), targets
// with names that are neither ARKit's nor Oculus', the file
// cut short, and a file that is not a GLB at all.
import { readFileSync, writeFileSync } from 'node:fs';

function chunks(bytes) {
  const jsonLength = bytes.readUInt32LE(12);
  return { json: JSON.parse(bytes.subarray(20, 20 + jsonLength).toString('utf8')), rest: bytes.subarray(20 + jsonLength) };
}

function assemble(json, rest) {
  let text = Buffer.from(JSON.stringify(json), 'utf8');
  text = Buffer.concat([text, Buffer.alloc((4 - (text.length % 4)) % 4, 0x20)]);
  const header = Buffer.alloc(20);
  header.write('glTF', 0, 'latin1');
  header.writeUInt32LE(2, 4);
  header.writeUInt32LE(20 + text.length + rest.length, 8);
  header.writeUInt32LE(text.length, 12);
  header.write('JSON', 16, 'latin1');
  return Buffer.concat([header, text, rest]);
}

/** The GLB with only the morph targets whose names `keep` accepts (in every primitive). */
export function keepTargets(bytes, keep) {
  const { json, rest } = chunks(bytes);
  for (const mesh of json.meshes) {
    const names = mesh.extras?.targetNames ?? [];
    const kept = names.map((name, i) => [name, i]).filter(([name]) => keep(name));
    for (const primitive of mesh.primitives) {
      if (primitive.targets) primitive.targets = kept.map(([, i]) => primitive.targets[i]);
      if (!primitive.targets?.length) delete primitive.targets;
    }
    if (mesh.weights) mesh.weights = kept.map(([, i]) => mesh.weights[i]);
    if (!kept.length) { delete mesh.weights; if (mesh.extras) delete mesh.extras.targetNames; }
    else mesh.extras.targetNames = kept.map(([name]) => name);
  }
  return assemble(json, rest);
}

/** The GLB with its morph targets renamed "Key 1", "Key 2", ... (Blender's default shape-key names). */
export function renameTargets(bytes) {
  const { json, rest } = chunks(bytes);
  for (const mesh of json.meshes) {
    if (mesh.extras?.targetNames) mesh.extras.targetNames = mesh.extras.targetNames.map((_, i) => `Key ${i + 1}`);
  }
  return assemble(json, rest);
}

/** Writes the test heads into `dir`; returns their paths by kind. */
export function writeTestHeads(headPath, dir) {
  const bytes = readFileSync(headPath);
  const heads = {
    arkit: [`${dir}/arkit_only.glb`, keepTargets(bytes, (name) => !name.startsWith('viseme_'))],
    oculus: [`${dir}/oculus_only.glb`, keepTargets(bytes, (name) => name.startsWith('viseme_'))],
    faceless: [`${dir}/no_face_shapes.glb`, renameTargets(bytes)],
    shapeless: [`${dir}/no_blend_shapes.glb`, keepTargets(bytes, () => false)],
    truncated: [`${dir}/truncated.glb`, bytes.subarray(0, Math.floor(bytes.length * 0.4))],
    notGlb: [`${dir}/not_a_head.glb`, Buffer.from('This is a text file, not a glTF binary.\n')],
  };
  for (const [path, data] of Object.values(heads)) writeFileSync(path, data);
  return Object.fromEntries(Object.entries(heads).map(([kind, [path]]) => [kind, path]));
}
