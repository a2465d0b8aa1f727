// Ruts in deformable soil (issue 30): every loaded cell of the soil's grid as a thin tile just
// above the undisturbed surface, darker the deeper the rut (the terrain is opaque, so a rut is
// drawn as a mark on the surface, coloured by its depth). A replay reads `ruts.csv` (the cells
// at the end, each with the time it was first loaded) and shows the cells made so far; a live
// view adds the cells of the server's `ruts` messages (live/hub.rs: [x, y, surface_z, depth,
// cell] rows; a cell that deepens comes again and is drawn again on top).

const LIFT_M = 0.0015; // above the surface, so the tile is not hidden in it
const THICK_M = 0.001;
/** Depth drawn darkest, m. */
export const RUT_FULL_DEPTH_M = 0.02;

/** Colour of a rut `depth` m deep: sand brown to dark brown. */
function colour(THREE, depth) {
  const k = Math.min(1, Math.max(0, depth / RUT_FULL_DEPTH_M));
  return new THREE.Color().setRGB(0.62 - 0.42 * k, 0.52 - 0.38 * k, 0.38 - 0.3 * k);
}

/** The rut layer of `world`. `add(rows)` appends cells ([x, y, surface_z, depth, cell, t]);
 * `showUntil(t)` shows the cells first loaded by time `t` (a replay: rows added in time order);
 * `count`, `deepest` describe what is drawn. */
export function createRuts(THREE, world) {
  const geometry = new THREE.BoxGeometry(1, 1, 1);
  const material = new THREE.MeshStandardMaterial({ color: 0xffffff, roughness: 1 });
  let capacity = 0, n = 0, mesh = null, times = [];
  const api = { count: 0, deepest: 0 };
  const dummy = new THREE.Object3D();
  function grow(need) {
    if (need <= capacity) return;
    const cap = Math.max(1024, 2 * need);
    const m = new THREE.InstancedMesh(geometry, material, cap);
    m.instanceMatrix.setUsage(THREE.DynamicDrawUsage);
    m.frustumCulled = false;
    if (mesh) {
      for (let i = 0; i < n; i++) {
        const mat = new THREE.Matrix4(); mesh.getMatrixAt(i, mat); m.setMatrixAt(i, mat);
        const c = new THREE.Color(); mesh.getColorAt(i, c); m.setColorAt(i, c);
      }
      world.remove(mesh); mesh.dispose();
    }
    mesh = m; capacity = cap; mesh.count = n;
    world.add(mesh);
  }
  api.add = (rows) => {
    if (!rows || rows.length === 0) return;
    grow(n + rows.length);
    for (const [x, y, z, depth, cell, t] of rows) {
      dummy.position.set(x, y, z + LIFT_M);
      dummy.scale.set(cell, cell, THICK_M);
      dummy.updateMatrix();
      mesh.setMatrixAt(n, dummy.matrix);
      mesh.setColorAt(n, colour(THREE, depth));
      times.push(Number.isFinite(t) ? t : 0);
      api.deepest = Math.max(api.deepest, depth);
      n++;
    }
    mesh.count = n;
    mesh.instanceMatrix.needsUpdate = true;
    if (mesh.instanceColor) mesh.instanceColor.needsUpdate = true;
    api.count = n;
  };
  api.clear = () => {
    n = 0; times = []; api.count = 0; api.deepest = 0;
    if (mesh) mesh.count = 0;
  };
  api.showUntil = (t) => {
    if (!mesh) return;
    // Rows were added sorted by time: the first k with times[i] <= t.
    let lo = 0, hi = n;
    while (lo < hi) { const mid = (lo + hi) >> 1; if (times[mid] <= t) lo = mid + 1; else hi = mid; }
    mesh.count = lo;
    api.count = lo;
  };
  return api;
}

/** The rows of `ruts.csv` text, sorted by the time each cell was first loaded. */
export function parseRuts(text) {
  const lines = text.trim().split('\n');
  const head = lines[0].split(',');
  const at = (name) => head.indexOf(name);
  const [ix, iy, iz, id, ic, it] = ['x_m', 'y_m', 'surface_z_m', 'depth_m', 'cell_m', 't_s'].map(at);
  const rows = lines.slice(1).map((l) => {
    const v = l.split(',').map(Number);
    return [v[ix], v[iy], v[iz], v[id], v[ic], v[it]];
  });
  rows.sort((a, b) => a[5] - b[5]);
  return rows;
}
