// What every test page shares: its result, failure and log POSTed to serve_page.mjs (/result,
// /fail, /log), uncaught errors as failures, console errors and warnings (shader logs, WebGL
// errors) in the test's log, bytes as base64 for the reports, and a quad that reads one level of
// a texture exactly.
import * as THREE from 'three';

export const post = (where, value) =>
    fetch(where, { method: 'POST', body: typeof value === 'string' ? value : JSON.stringify(value) });
export const fail = error => post('/fail', String((error && error.stack) || error));
window.addEventListener('error', e => fail(e.error || e.message));
window.addEventListener('unhandledrejection', e => fail(e.reason));
for (const level of ['error', 'warn']) {
    const original = console[level].bind(console);
    console[level] = (...parts) => {
        original(...parts);
        post('/log', `console.${level}: ${parts.map(String).join(' ')}`);
    };
}

export function base64(bytes) {
    let text = '';
    for (let i = 0; i < bytes.length; i += 0x8000)
        text += String.fromCharCode.apply(null, bytes.subarray(i, i + 0x8000));
    return btoa(text);
}

// A full-screen quad whose material fetches texel (x, y) of level `level` of `map` into pixel
// (x, y): drawn into a target of the level's size, it reads the level back exactly.
export function levelFetchQuad(map = null, level = 0) {
    const material = new THREE.RawShaderMaterial({
        glslVersion: THREE.GLSL3,
        uniforms: { map: { value: map }, level: { value: level } },
        vertexShader: `in vec3 position;
void main() { gl_Position = vec4(position.xy, 0.0, 1.0); }`,
        fragmentShader: `precision highp float;
uniform sampler2D map;
uniform int level;
out vec4 color;
void main() { color = texelFetch(map, ivec2(gl_FragCoord.xy), level); }`,
        depthTest: false, depthWrite: false,
    });
    const quad = new THREE.Mesh(new THREE.PlaneGeometry(2, 2), material);
    quad.frustumCulled = false;
    return quad;
}
