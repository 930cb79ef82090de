// The live view's page: draws the frames the server renders (asking for the
// next one only after the last is drawn), sends camera moves (one request
// in flight, the moves made meanwhile coalesced), keeps the controls in step
// with the shared view, and draws the BVH overlays. No framework, no network
// but this server.
'use strict';
(() => {
  const $ = (id) => document.getElementById(id);
  const image = $('image');
  const overlay = $('overlay');
  const imageContext = image.getContext('2d');
  const overlayContext = overlay.getContext('2d');
  const scratch = document.createElement('canvas');
  const scratchContext = scratch.getContext('2d');

  // What the tests and the measurement script read.
  const live = {framesDrawn: 0, frame: null, firstFrameMs: null, state: null, walk: null, level: null,
                navSent: 0, lastError: ''};
  window.ptLive = live;

  const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

  function showMessage(text, isError) {
    $('message').textContent = text;
    $('message').className = isError ? 'error' : '';
    if (isError) live.lastError = text;
  }

  async function request(method, path, params) {
    const query = params ? '?' + new URLSearchParams(params).toString() : '';
    // Every API request carries the header: the server refuses one without it (another site cannot send it).
    const init = {method, cache: 'no-store', headers: {'X-PT-Live': '1'}};
    const res = await fetch(path + query, init);
    const body = res.headers.get('Content-Type') === 'application/json' ? await res.json() : null;
    if (!res.ok) throw new Error((body && body.error) || (res.status + ' ' + res.statusText));
    return body;
  }

  // ------------------------------------------------------------ frames

  function draw(meta, pixels) {
    if (image.width !== meta.view_width || image.height !== meta.view_height) {
      image.width = meta.view_width;
      image.height = meta.view_height;
    }
    const data = new ImageData(pixels, meta.width, meta.height);
    if (meta.width === meta.view_width && meta.height === meta.view_height) {
      imageContext.putImageData(data, 0, 0);
    } else {  // a preview while the camera moves: scaled up
      scratch.width = meta.width;
      scratch.height = meta.height;
      scratchContext.putImageData(data, 0, 0);
      imageContext.imageSmoothingEnabled = true;
      imageContext.drawImage(scratch, 0, 0, meta.view_width, meta.view_height);
    }
    live.frame = meta;
    live.framesDrawn += 1;
    if (live.firstFrameMs === null) live.firstFrameMs = performance.now();
    drawOverlay();
    showStats(meta);
    if (live.state && meta.settings_version !== live.state.settings_version) refreshState();
  }

  const recentFrames = [];
  function showStats(meta) {
    const now = performance.now();
    recentFrames.push(now);
    while (recentFrames.length && now - recentFrames[0] > 1000) recentFrames.shift();
    const preview = meta.width < meta.view_width ? ' (1/' + Math.round(meta.view_width / meta.width) + ' res)' : '';
    $('stat-samples').textContent = meta.samples + ' / ' + meta.target + ' spp' + preview + (meta.complete ? ' done' : '');
    // The render's own estimate of its relative RMSE against the converged image (from 4 spp).
    $('stat-error').textContent = meta.estimated_relative_rmse === null ? ''
      : 'error ~' + (100 * meta.estimated_relative_rmse).toPrecision(2) + '%';
    $('stat-rays').textContent = meta.mrays.toFixed(1) + ' Mrays/s';
    $('stat-time').textContent = meta.seconds.toFixed(2) + ' s';
    $('stat-isa').textContent = live.state ? live.state.isa + ', ' + live.state.threads + ' threads' : '';
    $('stat-fps').textContent = recentFrames.length + ' frames/s';
  }

  // A hidden tab holds no request open (browsers allow six connections to a
  // server: open tabs must not use them up); it asks again once shown.
  let polling = null;
  const shown = () => new Promise((resolve) => {
    if (!document.hidden) return resolve();
    document.addEventListener('visibilitychange', function wait() {
      if (document.hidden) return;
      document.removeEventListener('visibilitychange', wait);
      resolve();
    });
  });
  document.addEventListener('visibilitychange', () => {
    if (document.hidden && polling) polling.abort();
  });

  // The next frame after `after`: the bytes, 'again' (none yet, or the tab was hidden) or 'lost' (with
  // the server's reason in frameError when it gave one: a failed render, a server stopping).
  let frameError = '';
  async function fetchFrame(after) {
    frameError = '';
    try {
      polling = new AbortController();
      const res = await fetch('/api/frame?after=' + after,
                              {cache: 'no-store', headers: {'X-PT-Live': '1'}, signal: polling.signal});
      if (res.status === 204) return 'again';
      if (res.ok) return await res.arrayBuffer();
      try {
        frameError = (await res.json()).error || '';
      } catch (e) {
        frameError = '';
      }
      return 'lost';
    } catch (e) {
      return e.name === 'AbortError' ? 'again' : 'lost';
    }
  }

  async function frameLoop() {
    let after = 0, lost = false;
    for (;;) {
      await shown();
      const buffer = await fetchFrame(after);
      if (buffer === 'again') continue;
      if (buffer === 'lost') {
        showMessage(frameError ? frameError + '; retrying' : 'connection to the server lost; retrying', true);
        lost = true;
        await sleep(1000);
        continue;
      }
      if (lost) showMessage('');
      lost = false;
      const length = new DataView(buffer).getUint32(0, true);
      const meta = JSON.parse(new TextDecoder().decode(new Uint8Array(buffer, 4, length)));
      draw(meta, new Uint8ClampedArray(buffer.slice(4 + length)));
      after = meta.id;  // back-pressure: the next frame is asked for only once this one is drawn
    }
  }

  // ------------------------------------------------------------ camera moves

  // Moves made while a request is in flight, summed; `moving`: a drag or the
  // wheel, which more moves follow (the server shows previews until `still`).
  const pending = {reset: false, orbit: [0, 0], pan: [0, 0], zoom: 0, moving: false, still: false};
  let navInFlight = false;

  function takeNav() {
    const moving = pending.moving ? {moving: 1} : {};
    if (pending.reset) {
      pending.reset = false;
      return {op: 'reset'};
    }
    for (const op of ['orbit', 'pan']) {
      const [dx, dy] = pending[op];
      if (dx !== 0 || dy !== 0) {
        pending[op] = [0, 0];
        return {op, dx: dx.toFixed(3), dy: dy.toFixed(3), ...moving};
      }
    }
    if (pending.zoom !== 0) {
      const steps = Math.max(-100, Math.min(100, pending.zoom));
      pending.zoom = 0;
      return {op: 'zoom', steps: steps.toFixed(3), ...moving};
    }
    pending.moving = false;
    if (pending.still) {  // after the last move of a drag: the view may accumulate
      pending.still = false;
      return {op: 'still'};
    }
    return null;
  }

  async function pumpNav() {
    if (navInFlight) return;
    const params = takeNav();
    if (!params) return;
    navInFlight = true;
    try {
      await request('POST', '/api/nav', params);
      live.navSent += 1;
    } catch (e) {
      showMessage(e.message, true);
    } finally {
      navInFlight = false;
    }
    pumpNav();
  }

  function move(op, dx, dy, moving) {
    pending[op][0] += dx;
    pending[op][1] += dy;
    pending.moving = pending.moving || moving;
    pumpNav();
  }

  let drag = null;
  // The pointer in pixels of the view (the image canvas's own pixels, whatever its size on screen).
  function canvasPoint(event) {
    const rect = overlay.getBoundingClientRect();
    return [(event.clientX - rect.left) * image.width / rect.width,
            (event.clientY - rect.top) * image.height / rect.height];
  }
  overlay.addEventListener('pointerdown', (event) => {
    overlay.setPointerCapture(event.pointerId);
    overlay.focus();
    const pan = event.button === 2 || event.button === 1 || event.shiftKey;
    drag = {id: event.pointerId, pan, start: canvasPoint(event), last: canvasPoint(event), moved: 0};
    event.preventDefault();
  });
  overlay.addEventListener('pointermove', (event) => {
    if (!drag || event.pointerId !== drag.id) return;
    const p = canvasPoint(event);
    const dx = p[0] - drag.last[0], dy = p[1] - drag.last[1];
    drag.last = p;
    drag.moved += Math.abs(dx) + Math.abs(dy);
    if (dx !== 0 || dy !== 0) move(drag.pan ? 'pan' : 'orbit', dx, dy, true);
  });
  const endDrag = (event) => {
    if (!drag || event.pointerId !== drag.id) return;
    const click = drag.moved < 3;
    const point = drag.start;
    drag = null;
    if (!click) {
      pending.still = true;
      pumpNav();
    } else if ($('walk').checked) {
      walkPixel(point[0], point[1]);
    }
  };
  overlay.addEventListener('pointerup', endDrag);
  overlay.addEventListener('pointercancel', endDrag);
  overlay.addEventListener('contextmenu', (event) => event.preventDefault());
  overlay.addEventListener('wheel', (event) => {
    event.preventDefault();
    const unit = event.deltaMode === 1 ? 1 / 3 : event.deltaMode === 2 ? 3 : 1 / 100;
    pending.zoom += event.deltaY * unit;
    pending.moving = true;  // wheels turn in bursts: the server waits out a short pause before accumulating
    pumpNav();
  }, {passive: false});
  document.addEventListener('keydown', (event) => {
    const tag = document.activeElement ? document.activeElement.tagName : '';
    if (tag === 'INPUT' || tag === 'SELECT' || event.ctrlKey || event.metaKey || event.altKey) return;
    const step = 20;
    const arrows = {ArrowLeft: [-step, 0], ArrowRight: [step, 0], ArrowUp: [0, -step], ArrowDown: [0, step]};
    if (arrows[event.key]) {
      move(event.shiftKey ? 'pan' : 'orbit', arrows[event.key][0], arrows[event.key][1], false);
    } else if (event.key === '+' || event.key === '=') {
      pending.zoom -= 1;
      pumpNav();
    } else if (event.key === '-' || event.key === '_') {
      pending.zoom += 1;
      pumpNav();
    } else if (event.key === 'r' || event.key === 'R') {
      pending.reset = true;
      pumpNav();
    } else if (event.key === 'n' || event.key === 'N') {
      const display = $('display').value === 'normals' ? 'image' : 'normals';
      changeSettings({display});
    } else {
      return;
    }
    event.preventDefault();
  });

  // ------------------------------------------------------------ settings

  const settingControls = ['samples', 'light', 'depth', 'display', 'bounces', 'direct', 'adaptive_tolerance',
                           'adaptive_batch', 'preview'];

  function showSettings(settings) {
    for (const name of settingControls) {
      const control = $(name);
      if (document.activeElement !== control) control.value = String(settings[name]);
    }
  }

  async function changeSettings(params) {
    try {
      const reply = await request('POST', '/api/settings', params);
      showSettings(reply.settings);
      showMessage('');
    } catch (e) {
      showMessage(e.message, true);
      if (live.state) showSettings(live.state.settings);
    }
  }

  for (const name of settingControls)
    $(name).addEventListener('change', () => changeSettings({[name]: $(name).value}));

  async function refreshState() {
    try {
      live.state = await request('GET', '/api/state');
      $('scene-name').textContent = live.state.scene;
      document.title = live.state.scene + ' - pathtracer live view';
      showSettings(live.state.settings);
    } catch (e) {
      showMessage(e.message, true);
    }
  }

  // ------------------------------------------------------------ BVH overlays

  const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
  const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];

  // A world point in the camera's frame: [x, y, depth in front of the camera].
  function toCamera(camera, p) {
    const d = sub(p, camera.position);
    return [dot(d, camera.screen_x), dot(d, camera.screen_y), -dot(d, camera.to_camera)];
  }
  // Pixel of a camera-frame point (depth > 0), as live/camera_nav.cpp's project_to_pixel.
  function toPixel(camera, width, height, c) {
    const x = c[0] / (c[2] * camera.tan_half_hfov), y = c[1] / (c[2] * camera.tan_half_vfov);
    return [(x + 1) * 0.5 * width, (1 - (y + 1) * 0.5) * height];
  }
  live.project = (p) => {
    const f = live.frame;
    const c = toCamera(f.camera, p);
    return c[2] > 0 ? toPixel(f.camera, f.view_width, f.view_height, c) : null;
  };

  // The twelve edges of a box, clipped to the space in front of the camera, in
  // the overlay's pixels (it is drawn at the screen's resolution, not the view's).
  function strokeBox(camera, box) {
    const sx = overlay.width / live.frame.view_width, sy = overlay.height / live.frame.view_height;
    const corner = (i) => [box[i & 1 ? 3 : 0], box[i & 2 ? 4 : 1], box[i & 4 ? 5 : 2]];
    const edges = [[0, 1], [2, 3], [4, 5], [6, 7], [0, 2], [1, 3], [4, 6], [5, 7], [0, 4], [1, 5], [2, 6], [3, 7]];
    const near = 1e-4;
    const points = [];
    for (let i = 0; i < 8; ++i) points.push(toCamera(camera, corner(i)));
    for (const [i, j] of edges) {
      let a = points[i], b = points[j];
      if (a[2] < near && b[2] < near) continue;
      if (a[2] < near || b[2] < near) {
        const t = (near - a[2]) / (b[2] - a[2]);
        const cut = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), near];
        if (a[2] < near) a = cut; else b = cut;
      }
      const pa = toPixel(camera, live.frame.view_width, live.frame.view_height, a);
      const pb = toPixel(camera, live.frame.view_width, live.frame.view_height, b);
      overlayContext.moveTo(pa[0] * sx, pa[1] * sy);
      overlayContext.lineTo(pb[0] * sx, pb[1] * sy);
    }
  }

  function drawOverlay() {
    const rect = overlay.getBoundingClientRect();
    const width = Math.max(1, Math.round(rect.width * devicePixelRatio));
    const height = Math.max(1, Math.round(rect.height * devicePixelRatio));
    if (overlay.width !== width || overlay.height !== height) {
      overlay.width = width;
      overlay.height = height;
    }
    overlayContext.clearRect(0, 0, overlay.width, overlay.height);
    const frame = live.frame;
    if (!frame) return;
    overlayContext.lineWidth = Math.max(1, devicePixelRatio);
    if (live.level) {
      overlayContext.beginPath();
      overlayContext.strokeStyle = 'rgba(120, 255, 140, 0.8)';
      for (const box of live.level.boxes) strokeBox(frame.camera, box);
      overlayContext.stroke();
    }
    if (live.walk) {
      const depths = Math.max(1, ...live.walk.visits.map((v) => v.depth));
      for (const visit of live.walk.visits) {
        overlayContext.beginPath();
        overlayContext.strokeStyle = visit.leaf ? 'rgba(255, 90, 90, 0.95)'
            : 'hsla(' + Math.round(200 - 160 * visit.depth / depths) + ', 90%, 60%, 0.7)';
        strokeBox(frame.camera, visit.box);
        overlayContext.stroke();
      }
      if (live.walk.hit) {
        const p = live.project(live.walk.hit.point);
        if (p) {
          overlayContext.beginPath();
          overlayContext.strokeStyle = '#ffffff';
          overlayContext.arc(p[0] * overlay.width / frame.view_width, p[1] * overlay.height / frame.view_height,
                             4 * devicePixelRatio, 0, 2 * Math.PI);
          overlayContext.stroke();
        }
      }
    }
  }

  async function showLevel() {
    const depth = $('bvh-depth').value;
    live.level = null;
    if (depth !== '') {
      try {
        live.level = await request('GET', '/api/bvh/level', {depth});
        if (live.level.truncated) showMessage('showing the first ' + live.level.boxes.length + ' boxes of this depth');
      } catch (e) {
        showMessage(e.message, true);
      }
    }
    drawOverlay();
  }
  $('bvh-depth').addEventListener('change', showLevel);

  async function fillDepths() {
    try {
      const level = await request('GET', '/api/bvh/level', {depth: 0});
      for (let d = 0; d <= level.max_depth; ++d) {
        const option = document.createElement('option');
        option.value = String(d);
        option.textContent = d === 0 ? '0 (root)' : String(d);
        $('bvh-depth').appendChild(option);
      }
    } catch (e) {
      showMessage(e.message, true);
    }
  }

  async function walkPixel(x, y) {
    try {
      live.walk = await request('GET', '/api/bvh/walk', {x: x.toFixed(2), y: y.toFixed(2)});
      const w = live.walk;
      $('walk-report').textContent = 'pixel (' + Math.floor(x) + ', ' + Math.floor(y) + '): ' + w.inner_nodes +
          ' inner nodes and ' + w.leaves + ' leaves visited; ' +
          (w.hit ? 'hit triangle ' + w.hit.prim + ' at t = ' + w.hit.t.toPrecision(5) : 'no triangle hit');
    } catch (e) {
      showMessage(e.message, true);
    }
    drawOverlay();
  }
  $('walk').addEventListener('change', () => {
    if (!$('walk').checked) {
      live.walk = null;
      $('walk-report').textContent = '';
      drawOverlay();
    }
  });

  // ------------------------------------------------------------ files

  const nameOf = (id) => {
    const name = $(id).value.trim();
    return name ? {name} : {};
  };

  $('reset').addEventListener('click', () => {
    pending.reset = true;
    pumpNav();
  });

  $('save-camera').addEventListener('click', async () => {
    try {
      const reply = await request('POST', '/api/camera/save', nameOf('camera-name'));
      showMessage('Saved ' + reply.file + ' (pathtracer -c renders this view)');
    } catch (e) {
      showMessage(e.message, true);
    }
  });

  async function followRender() {
    $('render').disabled = true;
    $('cancel-render').disabled = false;
    for (;;) {
      let job;
      try {
        job = await request('GET', '/api/render');
      } catch (e) {
        showMessage(e.message, true);
        break;
      }
      $('render-progress').value = job.progress;
      if (job.state !== 'rendering') {
        if (job.state === 'done') showMessage('Wrote ' + job.file);
        else showMessage('Render ' + job.state + (job.message ? ': ' + job.message : ''), job.state === 'failed');
        break;
      }
      await sleep(250);
    }
    $('render').disabled = false;
    $('cancel-render').disabled = true;
  }

  $('render').addEventListener('click', async () => {
    try {
      const reply = await request('POST', '/api/render', nameOf('image-name'));
      showMessage('Rendering ' + reply.file + ' (moving the camera cancels it)');
      followRender();
    } catch (e) {
      showMessage(e.message, true);
    }
  });
  $('cancel-render').addEventListener('click', () => request('POST', '/api/render/cancel').catch(() => {}));

  new ResizeObserver(() => drawOverlay()).observe(overlay);

  // ------------------------------------------------------------ start

  refreshState().then(() => {
    if (live.state.job.state === 'rendering') followRender();
  });
  fillDepths();
  frameLoop();
})();
