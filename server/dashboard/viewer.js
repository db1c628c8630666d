// The dashboard's mesh viewer: a finished job's time slice, its boundary surfaces drawn with
// three.js (WebGL), each interface in its own colour or each triangle by the quality of the
// pentatope it was cut from; rotate and zoom with the mouse, and a time that plays the cycle.
// Bundled with three.js at build time (server/CMakeLists.txt) and served as /viewer.js.
import {
  AmbientLight,
  BufferAttribute,
  BufferGeometry,
  Color,
  DirectionalLight,
  DoubleSide,
  Mesh,
  MeshLambertMaterial,
  PerspectiveCamera,
  Scene,
  Vector3,
  WebGLRenderer,
} from "three";
import { OrbitControls } from "three/addons/controls/OrbitControls.js";

// The slice surface's layout (docs/mesh-format.md, "Slice surfaces").
function decodeSurface(buffer) {
  const view = new DataView(buffer);
  const magic = String.fromCharCode(...new Uint8Array(buffer, 0, 4));
  if (magic !== "M4DS" || view.getUint32(4, true) !== 1)
    throw new Error("not a mesh4d slice surface (version 1)");
  const time = view.getFloat64(8, true);
  const span = [view.getFloat64(16, true), view.getFloat64(24, true)];
  const n = view.getUint32(32, true);
  const m = view.getUint32(36, true);
  let at = 40;
  const points = new Float32Array(buffer, at, 3 * n);
  at += 12 * n;
  const triangles = new Uint32Array(buffer, at, 3 * m);
  at += 12 * m;
  const labels = new Uint16Array(buffer, at, 2 * m);
  at += 4 * m;
  const ratio = new Float32Array(buffer, at, m);
  at += 4 * m;
  const volume = new Float32Array(buffer, at, m);
  return { time, span, points, triangles, labels, ratio, volume };
}

// Distinct colours for interfaces, in the order they are first met.
const PALETTE = ["#d1495b", "#00798c", "#edae49", "#66a182", "#8d5ba6", "#2e4057", "#f26419",
                 "#33658a", "#86bbd8", "#758e4f"];

// Quality scales: the colour of value x between good (blue) and bad (red).
const SCALES = {
  ratio: { name: "radius-edge ratio", low: 0.6, high: 2.0, worse: "high" },
  volume: { name: "normalized volume", low: 0.0, high: 0.6, worse: "low" },
};

function qualityColor(scale, x, out) {
  let s = (x - scale.low) / (scale.high - scale.low);
  s = Math.min(1, Math.max(0, s));
  if (scale.worse === "low") s = 1 - s;
  out.setHSL((1 - s) * 0.62, 0.75, 0.5);  // blue (good) to red (bad)
  return out;
}

export class SliceViewer {
  constructor(canvas) {
    this.canvas = canvas;
    this.renderer = new WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    this.scene = new Scene();
    this.scene.background = new Color("#f4f6f9");
    this.camera = new PerspectiveCamera(40, 1, 0.1, 1e5);
    this.scene.add(new AmbientLight(0xffffff, 0.55));
    this.light = new DirectionalLight(0xffffff, 1.6);
    this.scene.add(this.light);
    this.controls = new OrbitControls(this.camera, canvas);
    this.controls.addEventListener("change", () => this.render());
    this.meshes = [];
    this.seeThrough = false;
    this.colorBy = "interface";
    this.surface = null;
    this.fitted = false;
    this.interfaces = new Map();  // "inner/outer" -> colour, kept across times
    this.state = { triangles: 0, time: NaN, drawn: 0 };
    new ResizeObserver(() => this.resize()).observe(canvas);
    this.resize();
  }

  resize() {
    const w = this.canvas.clientWidth || 600, h = this.canvas.clientHeight || 400;
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.render();
  }

  render() {
    this.light.position.copy(this.camera.position);
    this.renderer.render(this.scene, this.camera);
  }

  // The slice at t of the job, decoded (its time span included); show() draws it.
  async fetchSurface(jobId, t) {
    const r = await fetch(`/v1/jobs/${encodeURIComponent(jobId)}/slices/${t}.surface`,
                          { credentials: "same-origin" });
    if (!r.ok) {
      const body = await r.json().catch(() => ({}));
      throw new Error(`${body.code || r.status}: ${body.message || "slice not available"}`);
    }
    return decodeSurface(await r.arrayBuffer());
  }

  show(surface) {
    this.surface = surface;
    this.draw();
  }

  setColorBy(mode) {
    this.colorBy = mode;
    if (this.surface) this.draw();
  }

  interfaceColor(inner, outer) {
    const key = `${inner}/${outer}`;
    if (!this.interfaces.has(key))
      this.interfaces.set(key, new Color(PALETTE[this.interfaces.size % PALETTE.length]));
    return this.interfaces.get(key);
  }

  // See-through: the surface against the outside drawn faint, so that the interfaces inside it
  // (a cavity within its wall) show.
  setSeeThrough(on) {
    this.seeThrough = on;
    if (this.surface) this.draw();
  }

  // Two triangle soups (three corners each, a colour per triangle): the triangles against the
  // outside, and those between two labels.
  draw() {
    const s = this.surface;
    const m = s.triangles.length / 3;
    const c = new Color();
    const scale = SCALES[this.colorBy];
    const parts = [[], []];  // triangle indices: against the outside, between labels
    for (let i = 0; i < m; ++i) parts[s.labels[2 * i + 1] === 0 ? 0 : 1].push(i);
    for (const mesh of this.meshes || []) {
      this.scene.remove(mesh);
      mesh.geometry.dispose();
      mesh.material.dispose();
    }
    this.meshes = parts.map((triangles, k) => {
      const position = new Float32Array(9 * triangles.length);
      const color = new Float32Array(9 * triangles.length);
      triangles.forEach((i, j) => {
        const col = scale
          ? qualityColor(scale, (this.colorBy === "ratio" ? s.ratio : s.volume)[i], c)
          : this.interfaceColor(s.labels[2 * i], s.labels[2 * i + 1]);
        for (let corner = 0; corner < 3; ++corner) {
          const p = s.triangles[3 * i + corner];
          for (let a = 0; a < 3; ++a) {
            position[9 * j + 3 * corner + a] = s.points[3 * p + a];
            color[9 * j + 3 * corner + a] = [col.r, col.g, col.b][a];
          }
        }
      });
      const geometry = new BufferGeometry();
      geometry.setAttribute("position", new BufferAttribute(position, 3));
      geometry.setAttribute("color", new BufferAttribute(color, 3));
      geometry.computeVertexNormals();
      const faint = k === 0 && this.seeThrough;
      const mesh = new Mesh(geometry, new MeshLambertMaterial({
        vertexColors: true, side: DoubleSide, flatShading: true, transparent: faint,
        opacity: faint ? 0.25 : 1, depthWrite: !faint }));
      mesh.renderOrder = faint ? 1 : 0;  // the faint surface over what it holds
      this.scene.add(mesh);
      return mesh;
    });
    if (!this.fitted && m > 0) this.fit(this.meshes[0].geometry.attributes.position.count
                                          ? this.meshes[0].geometry : this.meshes[1].geometry);
    this.state = { triangles: m, time: s.time, drawn: this.state.drawn + 1 };
    this.render();
  }

  // The camera looks at the first slice's box from a distance that shows all of it; later times
  // keep the user's view.
  fit(geometry) {
    geometry.computeBoundingSphere();
    const { center, radius } = geometry.boundingSphere;
    const distance = radius / Math.sin((this.camera.fov * Math.PI) / 360);
    this.camera.position.copy(center).add(new Vector3(0.6, -0.8, 0.5).normalize()
                                                 .multiplyScalar(distance));
    this.camera.up.set(0, 0, 1);
    this.camera.near = distance / 100;
    this.camera.far = distance * 10;
    this.camera.updateProjectionMatrix();
    this.controls.target.copy(center);
    this.controls.update();
    this.fitted = true;
  }

  // The legend's entries: [label text, CSS colour] per interface, or the quality scale's ends.
  legend() {
    const scale = SCALES[this.colorBy];
    if (scale) {
      const c = new Color();
      return [[`${scale.name} ${scale.low}`, `#${qualityColor(scale, scale.low, c).getHexString()}`],
              [`${scale.high}`, `#${qualityColor(scale, scale.high, c).getHexString()}`]];
    }
    return [...this.interfaces].map(([key, col]) => {
      const [inner, outer] = key.split("/");
      return [`label ${inner} | ${outer === "0" ? "outside" : "label " + outer}`,
              `#${col.getHexString()}`];
    });
  }
}
