// SPDX-License-Identifier: Apache-2.0
// The 3-D view of a job's T-mesh: its arcs as line segments (three.js r111 from Debian's
// libjs-three, embedded in the server), coloured by the quantization as it streams in. The
// geometry comes once from GET /v1/jobs/{id}/geometry (binary, server/http/mesh_geometry.h); the
// position and colour buffers are built once, and a new q only rewrites the colour buffer, at
// most once per animation frame, so that the page never waits on the view.
//
// Colour modes: the deviation q - s*l of each arc from its scaled target (diverging: blue where
// the arc was rounded down, grey where it kept its target, red where it was rounded up), q itself
// (a sequential scale), or what makes an arc critical (singular, feature, boundary). Arcs with
// q = 0 (collapsed) are drawn in magenta in the first two modes, whatever their deviation. When the
// job ends, the arcs of the separation rows its result enforces (the paths along which the run had
// to keep two critical entities apart) are drawn in green in every mode, unless that is switched
// off: a row names each bundle by one arc, and every drawn arc of that bundle is highlighted. The
// patches can be shown as translucent faces (off by default: in software WebGL a large mesh's
// faces cost more to draw than its lines).
//
// For tests and the curious, window.ispqView exposes the view's state: segments drawn, how many
// times the colours were rewritten, the q last drawn and the colour of any arc.
'use strict';

const MeshView = (() => {
  const MAGIC = 0x31475149;
  const FLAG = { critical: 1, singular: 2, feature: 4, boundary: 8 };
  const NO_Q = [0.62, 0.66, 0.72];      // before any quantization: the page's muted line colour
  const ZERO = [0.85, 0.0, 0.85];       // q = 0: magenta, whatever the mode
  const DOWN = [0.13, 0.40, 0.67];      // rounded down the most (#2166ac)
  const KEPT = [0.72, 0.74, 0.78];      // on target
  const UP = [0.70, 0.09, 0.17];        // rounded up the most (#b2182b)
  const Q_LOW = [0.99, 0.85, 0.46];     // q = 1 (#fdd976)
  const Q_HIGH = [0.10, 0.20, 0.55];    // the largest q
  const REGULAR = [0.78, 0.80, 0.84];
  const FACE_BOUNDARY = [0.45, 0.55, 0.70];  // translucent patches
  const FACE_INNER = [0.70, 0.76, 0.85];
  const SINGULAR = [0.80, 0.10, 0.10];
  const FEATURE = [0.90, 0.50, 0.0];
  const BOUNDARY_CRITICAL = [0.12, 0.43, 0.92];
  const SEPARATION_ROW = [0.11, 0.62, 0.47];  // #1b9e77: apart from both ends of every scale

  // The geometry response as typed arrays over its buffer (no copies).
  function parseGeometry(buffer) {
    const header = new Int32Array(buffer, 0, 8);
    if (header[0] !== MAGIC) throw new Error('not a geometry response');
    const nodes = header[1], sent = header[3];
    let offset = 32;
    const take = (Type, count) => {
      const array = new Type(buffer, offset, count);
      offset += count * Type.BYTES_PER_ELEMENT;
      return array;
    };
    const geometry = { nodes, arcs: header[2], sent, stride: header[4], bundles: header[5] };
    geometry.positions = take(Float32Array, 3 * nodes);
    geometry.arcIds = take(Int32Array, sent);
    geometry.ends = take(Int32Array, 2 * sent);
    geometry.lengths = take(Float32Array, sent);
    geometry.bundle = take(Int32Array, sent);
    geometry.flags = take(Uint8Array, sent);
    offset += (4 - sent % 4) % 4;
    geometry.patches = header[6];
    geometry.patchIds = take(Int32Array, header[6]);
    geometry.patchOffsets = take(Int32Array, header[6] + 1);
    geometry.cycleNodes = take(Int32Array, header[7]);
    geometry.patchFlags = take(Uint8Array, header[6]);
    offset += (4 - header[6] % 4) % 4;
    geometry.bundleFirstArc = take(Int32Array, header[5]);  // ascending: bundles are numbered by it
    return geometry;
  }

  function mix(a, b, t) {
    return [a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t, a[2] + (b[2] - a[2]) * t];
  }

  class View {
    // `elements`: {container, mode, reset, faces, rows, legend, tooltip, caption}.
    constructor(elements) {
      this.el = elements;
      this.mode = elements.mode.value;
      this.geometry = null;
      this.scaling = null;
      this.q = null;           // the latest q received, per arc of the mesh
      this.replayQ = null;     // an earlier q shown instead (the time cursor), or null
      this.drawnQ = null;      // the q the colours show
      this.final = false;
      this.recolours = 0;
      this.pending = false;
      this.firstDrawMs = null;
      this.range = 1;          // the deviation or q the scale ends at
      this.rows = [];          // the result's separation rows: [{arcs, coefficients, rhs}]
      this.rowsOfSegment = null;  // per drawn segment, the indices of the rows through its bundle
      elements.mode.addEventListener('change', () => { this.mode = elements.mode.value; this.schedule(); });
      elements.reset.addEventListener('click', () => this.resetCamera());
      elements.faces.addEventListener('change', () => this.showFaces(elements.faces.checked));
      elements.rows.addEventListener('change', () => this.schedule());
      this.setUp();
      this.publish();
    }

    // The renderer, scene, camera and controls, made once when the page loads and kept for every
    // job: creating a WebGL context and compiling its shaders takes a moment (long, in software),
    // which must not fall on the first seconds of a job, and browsers keep only a few contexts.
    setUp() {
      if (this.renderer || this.unavailable) return;
      try {
        // No multisampling: in software WebGL (headless Chromium, machines without a GPU) it made
        // every frame cost enough to hold up the rest of the page while a job streams.
        this.renderer = new THREE.WebGLRenderer({ antialias: false });
      } catch (error) {
        this.unavailable = 'WebGL is not available in this browser';
        return;
      }
      this.renderer.setPixelRatio(window.devicePixelRatio || 1);
      this.renderer.setClearColor(0xffffff);
      this.el.container.replaceChildren(this.renderer.domElement);
      this.scene = new THREE.Scene();
      this.material = new THREE.LineBasicMaterial({ vertexColors: THREE.VertexColors });
      this.faceMaterial = new THREE.MeshBasicMaterial({
        vertexColors: THREE.VertexColors, transparent: true, opacity: 0.18, side: THREE.DoubleSide,
        depthWrite: false });
      this.camera = new THREE.PerspectiveCamera(40, 760 / 480, 0.01, 100);
      this.controls = new THREE.OrbitControls(this.camera, this.renderer.domElement);
      this.controls.enableKeys = false;  // its arrow keys would steal the page's
      this.controls.addEventListener('change', () => this.render());
      this.raycaster = new THREE.Raycaster();
      // At most one raycast per frame: on a large mesh it visits every segment.
      this.renderer.domElement.addEventListener('mousemove', (event) => {
        const first = !this.hoverEvent;
        this.hoverEvent = event;
        if (first) requestAnimationFrame(() => { this.hover(this.hoverEvent); this.hoverEvent = null; });
      });
      this.renderer.domElement.addEventListener('mouseleave', () => { this.el.tooltip.hidden = true; });
      // Keyboard orbit for who does not use a mouse: the canvas takes focus (Tab) and its keys.
      const canvas = this.renderer.domElement;
      canvas.id = 'mesh-canvas';
      canvas.tabIndex = 0;
      canvas.setAttribute('role', 'img');
      canvas.setAttribute('aria-label', '3-D view of the T-mesh: arrow keys orbit, + and − zoom, ' +
                                        '0 resets the view');
      canvas.addEventListener('keydown', (event) => this.key(event));
      // Compiles the line shader now, on one segment, rather than when the first job is drawn.
      const warm = new THREE.BufferGeometry();
      warm.setAttribute('position', new THREE.BufferAttribute(new Float32Array(6), 3));
      warm.setAttribute('color', new THREE.BufferAttribute(new Float32Array(6), 3));
      const segment = new THREE.LineSegments(warm, this.material);
      this.scene.add(segment);
      this.renderer.setSize(1, 1);
      this.renderer.render(this.scene, this.camera);
      this.scene.remove(segment);
      warm.dispose();
    }

    // Drops the current mesh (another job is followed).
    clear() {
      if (this.lines) {
        this.scene.remove(this.lines);
        this.lines.geometry.dispose();
      }
      if (this.faces) {
        this.scene.remove(this.faces);
        this.faces.geometry.dispose();
      }
      Object.assign(this, { geometry: null, q: null, replayQ: null, drawnQ: null, final: false,
                            drawnFinal: false, recolours: 0, firstDrawMs: null, scaling: null,
                            lines: null, faces: null, triangles: 0, rows: [],
                            rowsOfSegment: null });
      this.render();
      this.el.caption.textContent = '';
      this.el.legend.replaceChildren();
      this.publish();
    }

    // Builds the segments once from the geometry response and draws them.
    show(buffer, startedAt) {
      this.setUp();
      if (this.unavailable) throw new Error(this.unavailable);
      const g = parseGeometry(buffer);
      this.geometry = g;
      const positions = new Float32Array(6 * g.sent);
      for (let i = 0; i < g.sent; i++) {
        for (let end = 0; end < 2; end++) {
          const node = g.ends[2 * i + end];
          positions.set(g.positions.subarray(3 * node, 3 * node + 3), 6 * i + 3 * end);
        }
      }
      this.colours = new Float32Array(6 * g.sent);
      const buffers = new THREE.BufferGeometry();
      buffers.setAttribute('position', new THREE.BufferAttribute(positions, 3));
      this.colourAttribute = new THREE.BufferAttribute(this.colours, 3);
      this.colourAttribute.setUsage(THREE.DynamicDrawUsage);
      buffers.setAttribute('color', this.colourAttribute);
      buffers.computeBoundingSphere();
      this.lines = new THREE.LineSegments(buffers, this.material);
      this.scene.add(this.lines);
      if (this.el.faces.checked) this.showFaces(true);

      const container = this.el.container;
      const width = container.clientWidth || 760, height = container.clientHeight || 480;
      this.renderer.setSize(width, height);
      const sphere = buffers.boundingSphere;
      this.camera.aspect = width / height;
      this.camera.near = sphere.radius / 100;
      this.camera.far = sphere.radius * 100;
      this.camera.updateProjectionMatrix();
      this.raycaster.params.Line.threshold = sphere.radius / 150;
      this.resetCamera();

      this.el.caption.textContent = g.sent === g.arcs
        ? g.arcs + ' arcs, ' + g.nodes + ' nodes'
        : 'decimated: ' + g.sent + ' of ' + g.arcs + ' arcs shown (every critical arc and 1 in ' +
          g.stride + ' of the others), ' + g.nodes + ' nodes';
      this.markRows();
      this.recolour();
      if (startedAt !== undefined) this.firstDrawMs = performance.now() - startedAt;
      this.publish();
    }

    // Arrow keys orbit by 10 degrees, + and - zoom, 0 or Home resets.
    key(event) {
      if (!this.lines) return;
      const step = Math.PI / 18;
      const offset = this.camera.position.clone().sub(this.controls.target);
      const spherical = new THREE.Spherical().setFromVector3(offset);
      const turns = { ArrowLeft: [-step, 0], ArrowRight: [step, 0], ArrowUp: [0, -step], ArrowDown: [0, step] };
      if (turns[event.key]) {
        spherical.theta += turns[event.key][0];
        spherical.phi = Math.min(Math.PI - 0.01, Math.max(0.01, spherical.phi + turns[event.key][1]));
      } else if (event.key === '+' || event.key === '=') {
        spherical.radius /= 1.2;
      } else if (event.key === '-' || event.key === '_') {
        spherical.radius *= 1.2;
      } else if (event.key === '0' || event.key === 'Home') {
        event.preventDefault();
        this.resetCamera();
        return;
      } else {
        return;  // Tab and the rest keep their meaning
      }
      event.preventDefault();
      this.camera.position.copy(this.controls.target).add(new THREE.Vector3().setFromSpherical(spherical));
      this.camera.lookAt(this.controls.target);
      this.controls.update();
      this.render();
    }

    // The patches as translucent faces (each cycle a fan of triangles around its first node):
    // boundary patches a little darker, so that the part's shape shows through its inside.
    patchFaces(g) {
      let triangles = 0;
      for (let i = 0; i < g.patches; i++) triangles += g.patchOffsets[i + 1] - g.patchOffsets[i] - 2;
      const positions = new Float32Array(9 * Math.max(0, triangles));
      const colours = new Float32Array(9 * Math.max(0, triangles));
      let t = 0;
      for (let i = 0; i < g.patches; i++) {
        const first = g.patchOffsets[i], end = g.patchOffsets[i + 1];
        const colour = g.patchFlags[i] & FLAG.boundary ? FACE_BOUNDARY : FACE_INNER;
        for (let k = first + 1; k + 1 < end; k++) {
          for (const [corner, node] of [[0, g.cycleNodes[first]], [1, g.cycleNodes[k]], [2, g.cycleNodes[k + 1]]]) {
            positions.set(g.positions.subarray(3 * node, 3 * node + 3), 9 * t + 3 * corner);
            colours.set(colour, 9 * t + 3 * corner);
          }
          t++;
        }
      }
      const buffers = new THREE.BufferGeometry();
      buffers.setAttribute('position', new THREE.BufferAttribute(positions, 3));
      buffers.setAttribute('color', new THREE.BufferAttribute(colours, 3));
      this.triangles = triangles;
      return new THREE.Mesh(buffers, this.faceMaterial);
    }

    // Built on first request only: the page must not pay for faces it does not show.
    showFaces(visible) {
      if (!this.geometry) return;
      if (visible && !this.faces) {
        this.faces = this.patchFaces(this.geometry);
        this.scene.add(this.faces);
      }
      if (this.faces) this.faces.visible = visible;
      this.render();
    }

    resetCamera() {
      if (!this.lines) return;
      const sphere = this.lines.geometry.boundingSphere;
      const distance = sphere.radius / Math.sin((this.camera.fov / 2) * Math.PI / 180) * 1.05;
      const direction = new THREE.Vector3(1, 0.8, 1.3).normalize();
      this.camera.position.copy(sphere.center).addScaledVector(direction, distance);
      this.controls.target.copy(sphere.center);
      this.camera.lookAt(sphere.center);
      this.controls.update();
      this.render();
    }

    // The job's resolved scaling s (targets are s * l).
    setScaling(scaling) {
      if (Number.isFinite(scaling) && scaling > 0) { this.scaling = scaling; this.schedule(); }
    }

    // A quantization: an intermediate one, or the final result's (`final`).
    setQ(q, final) {
      if (!q || this.final) return;
      this.q = q;
      this.final = !!final;
      this.schedule();
    }

    // The final result's separation rows (QuantizationResult.separation_rows in its JSON form).
    setSeparationRows(rows) {
      this.rows = Array.isArray(rows) ? rows : [];
      this.markRows();
      this.schedule();
    }

    // Which rows pass through each drawn segment's bundle. A row names each bundle by its smallest
    // arc, found among the bundles' smallest arcs even when a decimated view did not send it.
    markRows() {
      const g = this.geometry;
      if (!g) return;
      this.rowsOfSegment = null;
      if (!this.rows.length) return;
      const rowsOfBundle = new Map();
      this.rows.forEach((row, r) => {
        for (const arc of row.arcs || []) {
          const b = this.bundleNamedBy(arc);
          if (b < 0) continue;
          if (!rowsOfBundle.has(b)) rowsOfBundle.set(b, []);
          const list = rowsOfBundle.get(b);
          if (list[list.length - 1] !== r) list.push(r);
        }
      });
      this.rowsOfSegment = new Array(g.sent);
      for (let i = 0; i < g.sent; i++) this.rowsOfSegment[i] = rowsOfBundle.get(g.bundle[i]) || null;
    }

    // The bundle whose smallest arc is `arc`, or -1.
    bundleNamedBy(arc) {
      const first = this.geometry.bundleFirstArc;
      let lo = 0, hi = first.length - 1;
      while (lo <= hi) {
        const mid = (lo + hi) >> 1;
        if (first[mid] === arc) return mid;
        if (first[mid] < arc) lo = mid + 1; else hi = mid - 1;
      }
      return -1;
    }

    highlightsRow(i) {
      return this.el.rows.checked && this.rowsOfSegment !== null && this.rowsOfSegment[i] !== null;
    }

    // Shows an earlier quantization instead of the latest (null: the latest again).
    replay(q) {
      if (q === this.replayQ) return;
      this.replayQ = q || null;
      this.schedule();
    }

    // Recolours at the next animation frame: a burst of intermediate quantizations costs one.
    schedule() {
      if (!this.geometry || this.pending) return;
      this.pending = true;
      requestAnimationFrame(() => { this.pending = false; this.recolour(); });
    }

    colourFor(i, q) {
      const g = this.geometry, flags = g.flags[i];
      if (q !== 0 && this.highlightsRow(i)) return SEPARATION_ROW;
      if (this.mode === 'criticality') {
        if (flags & FLAG.singular) return SINGULAR;
        if (flags & FLAG.feature) return FEATURE;
        if (flags & FLAG.critical) return BOUNDARY_CRITICAL;
        return REGULAR;
      }
      if (q === undefined || q === null) return NO_Q;
      if (q === 0) return ZERO;
      if (this.mode === 'q') return mix(Q_LOW, Q_HIGH, Math.min(1, (q - 1) / Math.max(1, this.range - 1)));
      const deviation = q - (this.scaling || 1) * g.lengths[i];
      const t = Math.max(-1, Math.min(1, deviation / this.range));
      return t < 0 ? mix(KEPT, DOWN, -t) : mix(KEPT, UP, t);
    }

    recolour() {
      const g = this.geometry;
      if (!g || !this.renderer) return;
      const q = this.replayQ || this.q;
      // The scale's end: the largest |deviation| (at least 1/2) or the largest q.
      this.range = this.mode === 'q' ? 1 : 0.5;
      if (q) {
        for (let i = 0; i < g.sent; i++) {
          const value = q[g.arcIds[i]];
          const extent = this.mode === 'q' ? value : Math.abs(value - (this.scaling || 1) * g.lengths[i]);
          if (extent > this.range) this.range = extent;
        }
      }
      for (let i = 0; i < g.sent; i++) {
        const colour = this.colourFor(i, q ? q[g.arcIds[i]] : undefined);
        this.colours.set(colour, 6 * i);
        this.colours.set(colour, 6 * i + 3);
      }
      this.colourAttribute.needsUpdate = true;
      this.drawnQ = q;
      this.drawnFinal = this.final && q === this.q && !this.replayQ;
      if (q) this.recolours++;
      this.legend();
      this.render();
      this.publish();
    }

    render() {
      if (this.renderer) this.renderer.render(this.scene, this.camera);
    }

    legend() {
      const legend = this.el.legend;
      const swatch = (colour, text) => {
        const item = document.createElement('span');
        const box = document.createElement('span');
        box.className = 'swatch';
        box.style.background = 'rgb(' + colour.map((c) => Math.round(c * 255)).join(',') + ')';
        item.append(box, ' ' + text);
        return item;
      };
      const items = [];
      if (this.mode === 'criticality') {
        items.push(swatch(SINGULAR, 'singular'), swatch(FEATURE, 'feature'),
                   swatch(BOUNDARY_CRITICAL, 'other critical'), swatch(REGULAR, 'regular'));
      } else if (!this.drawnQ) {
        items.push(swatch(NO_Q, 'waiting for a quantization'));
      } else if (this.mode === 'q') {
        items.push(swatch(Q_LOW, 'q = 1'), swatch(mix(Q_LOW, Q_HIGH, 0.5), 'q = ' + Math.round((1 + this.range) / 2)),
                   swatch(Q_HIGH, 'q = ' + this.range), swatch(ZERO, 'q = 0'));
      } else {
        const r = +this.range.toFixed(2);
        items.push(swatch(DOWN, '−' + r + ' (rounded down)'), swatch(mix(KEPT, DOWN, 0.5), '−' + +(r / 2).toFixed(2)),
                   swatch(KEPT, '0'), swatch(mix(KEPT, UP, 0.5), '+' + +(r / 2).toFixed(2)),
                   swatch(UP, '+' + r + ' (rounded up)'), swatch(ZERO, 'q = 0'));
      }
      if (this.rows.length && this.el.rows.checked) {
        const n = this.rows.length;
        items.push(swatch(SEPARATION_ROW, 'the arcs of the ' + n + ' separation row' + (n === 1 ? '' : 's')));
      }
      if (this.drawnQ) {
        const which = this.replayQ ? 'an earlier q (time cursor)' : this.final ? 'final q' : 'intermediate q';
        items.push(document.createTextNode(' · ' + which));
      }
      legend.replaceChildren(...items);
    }

    hover(event) {
      if (!this.geometry) return;
      const rect = this.renderer.domElement.getBoundingClientRect();
      const mouse = new THREE.Vector2(((event.clientX - rect.left) / rect.width) * 2 - 1,
                                      -((event.clientY - rect.top) / rect.height) * 2 + 1);
      this.raycaster.setFromCamera(mouse, this.camera);
      const hit = this.raycaster.intersectObject(this.lines)[0];
      const tooltip = this.el.tooltip;
      if (!hit) { tooltip.hidden = true; return; }
      const i = Math.floor(hit.index / 2), g = this.geometry, arc = g.arcIds[i];
      const target = (this.scaling || 1) * g.lengths[i];
      const q = this.drawnQ ? this.drawnQ[arc] : undefined;
      const kinds = ['critical', 'singular', 'feature', 'boundary'].filter((k) => g.flags[i] & FLAG[k]);
      tooltip.textContent = 'arc ' + arc + ' · target ' + target.toFixed(3) +
        ' · q ' + (q === undefined ? '—' : q) + ' · bundle ' + g.bundle[i] +
        (kinds.length ? ' · ' + kinds.join(', ') : '') + this.rowsText(i);
      tooltip.style.left = (event.clientX - rect.left + 12) + 'px';
      tooltip.style.top = (event.clientY - rect.top + 12) + 'px';
      tooltip.hidden = false;
    }

    // " · separation rows 3, 7" for a segment whose bundle is on rows (numbered from 1).
    rowsText(i) {
      const rows = this.rowsOfSegment ? this.rowsOfSegment[i] : null;
      if (!rows) return '';
      const shown = rows.slice(0, 5).map((r) => r + 1).join(', ');
      return ' · separation row' + (rows.length === 1 ? ' ' : 's ') + shown +
             (rows.length > 5 ? ' and ' + (rows.length - 5) + ' more' : '');
    }

    // The segment of `arc` (an id of the mesh; the ids sent ascend), or -1 if it is not drawn.
    indexOf(arc) {
      const g = this.geometry;
      if (!g) return -1;
      let lo = 0, hi = g.sent - 1;
      while (lo <= hi) {
        const mid = (lo + hi) >> 1;
        if (g.arcIds[mid] === arc) return mid;
        if (g.arcIds[mid] < arc) lo = mid + 1; else hi = mid - 1;
      }
      return -1;
    }

    // The colour drawn for `arc`, or null if it is not drawn.
    colourOf(arc) {
      const i = this.indexOf(arc);
      return i < 0 ? null : Array.from(this.colours.subarray(6 * i, 6 * i + 3));
    }

    // What the tests read (window.ispqView): a live view of this object's state.
    publish() {
      if (window.ispqView && window.ispqView.owner === this) return;
      const view = this;
      window.ispqView = {
        owner: view,
        get segments() { return view.lines ? view.lines.geometry.attributes.position.count / 2 : 0; },
        get arcs() { return view.geometry ? view.geometry.arcs : 0; },
        get stride() { return view.geometry ? view.geometry.stride : 0; },
        get recolours() { return view.recolours; },
        get final() { return !!view.drawnFinal; },  // the final q is what the colours show
        get replaying() { return view.replayQ !== null; },
        get mode() { return view.mode; },
        get scaling() { return view.scaling; },
        get firstDrawMs() { return view.firstDrawMs; },
        get patches() { return view.geometry ? view.geometry.patches : 0; },
        get triangles() { return view.triangles || 0; },
        get facesShown() { return !!(view.faces && view.faces.visible); },
        get camera() { return view.camera ? view.camera.position.toArray() : null; },
        get q() { return view.drawnQ; },
        get separationRows() { return view.rows.length; },
        // The arcs on the separation rows while they are shown (green, or magenta if q = 0).
        get rowArcs() {
          const g = view.geometry;
          return g ? Array.from(g.arcIds).filter((arc, i) => view.highlightsRow(i)) : [];
        },
        get arcIds() { return view.geometry ? Array.from(view.geometry.arcIds) : []; },
        colourOf: (arc) => view.colourOf(arc),
        // Where the middle of `arc` is drawn, in the page's client coordinates (to hover it).
        screenPointOf: (arc) => {
          const i = view.indexOf(arc);
          if (i < 0) return null;
          const p = view.lines.geometry.attributes.position.array;
          const middle = new THREE.Vector3((p[6 * i] + p[6 * i + 3]) / 2, (p[6 * i + 1] + p[6 * i + 4]) / 2,
                                           (p[6 * i + 2] + p[6 * i + 5]) / 2).project(view.camera);
          const rect = view.renderer.domElement.getBoundingClientRect();
          return [rect.left + (middle.x + 1) / 2 * rect.width, rect.top + (1 - middle.y) / 2 * rect.height];
        },
        // The colour arc `arc` gets for a given q in the current mode and scale.
        expectedColour: (arc, q) => {
          const i = view.indexOf(arc);
          return i < 0 ? null : Array.from(new Float32Array(view.colourFor(i, q)));
        },
      };
    }
  }

  return { View, parseGeometry };
})();
