// The views the web player draws, as the native tools make them: a capture
// camera's view and projection (player/render/renderer.h,
// CameraViewProjection), a look-at view with a perspective projection (fvv
// render's orbit and camera paths). Column-major Float32Array(16), as WebGL
// takes them.

export function multiply(a, b) {
  const out = new Float32Array(16);
  for (let c = 0; c < 4; ++c) {
    for (let r = 0; r < 4; ++r) {
      let s = 0;
      for (let k = 0; k < 4; ++k) s += a[k * 4 + r] * b[c * 4 + k];
      out[c * 4 + r] = s;
    }
  }
  return out;
}

// The inverse of a rigid or affine transform (the last row 0 0 0 1).
export function invert(m) {
  // The 3x3 part's inverse by cofactors, then the translation.
  const a = [m[0], m[1], m[2]], b = [m[4], m[5], m[6]], c = [m[8], m[9], m[10]];
  const bc = cross(b, c), ca = cross(c, a), ab = cross(a, b);
  const det = dot(a, bc);
  const r = [bc.map((v) => v / det), ca.map((v) => v / det), ab.map((v) => v / det)];  // rows
  const out = new Float32Array(16);
  for (let row = 0; row < 3; ++row) {
    for (let col = 0; col < 3; ++col) out[col * 4 + row] = r[row][col];
  }
  const t = [m[12], m[13], m[14]];
  for (let row = 0; row < 3; ++row) out[12 + row] = -dot(r[row], t);
  out[15] = 1;
  return out;
}

export function transformPoint(m, p) {
  return [0, 1, 2].map((r) => m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r]);
}

const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const normalize = (a) => { const l = Math.hypot(...a); return a.map((v) => v / l); };

// glm::lookAt (right-handed).
export function lookAt(eye, target, up = [0, 1, 0]) {
  const f = normalize(sub(target, eye)), s = normalize(cross(f, up)), u = cross(s, f);
  return new Float32Array([s[0], u[0], -f[0], 0, s[1], u[1], -f[1], 0, s[2], u[2], -f[2], 0,
    -dot(s, eye), -dot(u, eye), dot(f, eye), 1]);
}

// glm::perspective: vertical field of view in degrees.
export function perspective(fovDeg, aspect, near, far) {
  const t = 1 / Math.tan((fovDeg * Math.PI) / 360);
  const p = new Float32Array(16);
  p[0] = t / aspect;
  p[5] = t;
  p[10] = -(far + near) / (far - near);
  p[11] = -1;
  p[14] = (-2 * far * near) / (far - near);
  return p;
}

// A capture camera (OpenCV conventions: x right, y down, z forward; pixel
// centres at integers) as a GL view and projection.
export function cameraViewProjection(c, near, far) {
  const viewMatrix = new Float32Array(16);
  for (let r = 0; r < 3; ++r) {
    const sign = r === 0 ? 1 : -1;  // y and z flipped for GL
    for (let k = 0; k < 3; ++k) viewMatrix[k * 4 + r] = sign * c.rotation[3 * r + k];
    viewMatrix[12 + r] = sign * c.translation[r];
  }
  viewMatrix[15] = 1;
  const w = c.width, h = c.height, p = new Float32Array(16);
  p[0] = (2 * c.fx) / w;
  p[5] = (2 * c.fy) / h;
  p[8] = 1 - (2 * (c.cx + 0.5)) / w;
  p[9] = (2 * (c.cy + 0.5)) / h - 1;
  p[10] = -(far + near) / (far - near);
  p[11] = -1;
  p[14] = (-2 * far * near) / (far - near);
  return { viewMatrix, projection: p };
}

// The orbit a viewer turns round the actor: `yaw` and `pitch` in radians,
// `distance` in metres, looking at `target`; fvv render's orbit at pitch 0
// is yaw = angle, distance 3.5 with the eye 0.4 m above the target.
export function orbitView(target, { yaw, pitch, distance, fovDeg = 40, aspect }) {
  const eye = [
    target[0] + distance * Math.cos(pitch) * Math.sin(yaw),
    target[1] + distance * Math.sin(pitch),
    target[2] + distance * Math.cos(pitch) * Math.cos(yaw),
  ];
  return lookAtView(eye, target, fovDeg, aspect);
}

export function lookAtView(eye, target, fovDeg, aspect) {
  return { eye, target, viewMatrix: lookAt(eye, target), projection: perspective(fovDeg, aspect, 0.05, 50) };
}

// The point the cameras look at: nearest (least squares) to every camera's
// optical axis, the rig's aim, where the actor stands. Cameras in the
// stream's form (centre, rotation: world to camera, row-major). Null when
// the axes do not fix a point (fewer than two, or all parallel).
export function lookedAtPoint(cameras) {
  const a = [0, 0, 0, 0, 0, 0, 0, 0, 0], b = [0, 0, 0];
  for (const c of cameras) {
    const d = [c.rotation[6], c.rotation[7], c.rotation[8]];  // the optical axis in the world
    for (let r = 0; r < 3; ++r) {
      for (let k = 0; k < 3; ++k) {
        const m = (r === k ? 1 : 0) - d[r] * d[k];
        a[r * 3 + k] += m;
        b[r] += m * c.centre[k];
      }
    }
  }
  // Cramer's rule on the 3x3 system a p = b.
  const det = (m) => m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) +
    m[2] * (m[3] * m[7] - m[4] * m[6]);
  const d = det(a);
  if (!(Math.abs(d) > 1e-9 * Math.max(1, cameras.length ** 3))) return null;
  return [0, 1, 2].map((col) => det(a.map((v, i) => (i % 3 === col ? b[Math.floor(i / 3)] : v))) / d);
}
