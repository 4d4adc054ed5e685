// Renders an ndfmip scene (?scene=, docs/SCENES.md: a plane, a perspective or orthographic
// camera, directional and point lights, a GGX material) with three.js's MeshStandardMaterial
// shaded by the vMF module (/ndfmip/ndfmip_vmf.js) from the bake's lobe textures (?lobes=, KTX2),
// into a float target read back as linear RGB, as `ndfmip render --gpu` writes its EXR. Then
// times ?frames= frames of it and of a stock MeshStandardMaterial with the map (?normal=, a PNG
// three mipmaps itself) as its normalMap, each frame drawn to the canvas and waited for
// (readPixels of one pixel). Last, the module under an environment (three's RoomEnvironment): the
// mean radiance without and with it. POSTs {three, renderer, width, height, pixels (base64
// float32 RGBA, bottom row first), frameMs: {vmf, standard}, environment} to /result, or the
// error to /fail.
import * as THREE from 'three';
import { KTX2Loader } from 'three/addons/loaders/KTX2Loader.js';
import { RoomEnvironment } from 'three/addons/environments/RoomEnvironment.js';
import { loadVmfLobes, useVmfLobes } from '/ndfmip/ndfmip_vmf.js';

import { base64, fail, post } from './page_report.mjs';

const colour = (value, fallback) =>
    value === undefined ? fallback : Array.isArray(value) ? value : [value, value, value];

// The scene's camera, plane and lights in three's terms (ndfmip's conventions: src/render).
function buildScene(json) {
    const c = json.camera, o = json.object;
    if (o.type !== 'plane') throw new Error('only plane scenes');
    const aspect = c.width / c.height;
    const camera = c.type === 'orthographic'
        ? new THREE.OrthographicCamera(-0.5 * c.ortho_height * aspect, 0.5 * c.ortho_height * aspect,
                                       0.5 * c.ortho_height, -0.5 * c.ortho_height, 0.05, 1000)
        : new THREE.PerspectiveCamera(c.fov, aspect, 0.05, 1000);
    camera.position.set(...c.eye);
    camera.up.set(...c.up);
    camera.lookAt(new THREE.Vector3(...c.target));
    camera.updateMatrixWorld();

    // The plane: PlaneGeometry's x, y, z onto ndfmip's tangent, bitangent = normal x tangent, normal.
    const normal = new THREE.Vector3(...o.normal).normalize();
    const tangent = new THREE.Vector3(...o.tangent).normalize();
    const bitangent = new THREE.Vector3().crossVectors(normal, tangent);
    // Cut into 64 x 64 quads: the rasteriser's perspective interpolation of uv across a triangle
    // clipped far behind the near plane loses precision (1/w of the clipped vertices), and one
    // texel's worth of uv error is visible in a map of this detail.
    const geometry = new THREE.PlaneGeometry(o.size[0], o.size[1], 64, 64);
    const scene = new THREE.Scene();
    const lights = [];
    for (const l of json.lights) {
        const lightColour = new THREE.Color(...colour(l.color, [1, 1, 1]));
        const intensity = l.intensity === undefined ? 1 : l.intensity;
        let light;
        if (l.type === 'directional') {
            light = new THREE.DirectionalLight(lightColour, intensity);
            light.position.set(...l.direction).normalize();
        } else {
            light = new THREE.PointLight(lightColour, intensity, 0, 2); // 1/d²
            light.position.set(...l.position);
        }
        lights.push(light);
        scene.add(light);
    }
    const place = mesh => {
        mesh.matrixAutoUpdate = false;
        mesh.matrix.makeBasis(tangent, bitangent, normal).setPosition(...(o.center || [0, 0, 0]));
        mesh.frustumCulled = false;
        return mesh;
    };
    return { camera, scene, geometry, place, tiling: o.tiling || [1, 1] };
}

async function main() {
    const params = new URLSearchParams(location.search);
    const json = await (await fetch(params.get('scene'))).json();
    const { width, height } = json.camera;
    const canvas = document.createElement('canvas');
    canvas.width = width;
    canvas.height = height;
    document.body.appendChild(canvas);
    const renderer = new THREE.WebGLRenderer({ canvas, antialias: false });
    renderer.setPixelRatio(1);
    renderer.setSize(width, height, false);
    renderer.toneMapping = THREE.NoToneMapping;
    renderer.setClearColor(new THREE.Color(...colour(json.background, [0, 0, 0])), 1);
    const gl = renderer.getContext();

    const ktx2 = new KTX2Loader().setTranscoderPath('/three/examples/jsm/libs/basis/').detectSupport(renderer);
    const lobes = await loadVmfLobes(ktx2, params.get('lobes').split(','));
    const { camera, scene, geometry, place, tiling } = buildScene(json);
    const m = json.material;
    if (m.brdf !== 'ggx') throw new Error('only GGX materials (three.js is GGX)');
    const material = new THREE.MeshStandardMaterial({
        color: new THREE.Color(...colour(m.albedo, [0.5, 0.5, 0.5])),
        roughness: Math.sqrt(m.roughness), metalness: 0,
    });
    useVmfLobes(material, { lobes, tiling, specular: colour(m.specular, [1, 1, 1]) });
    const mesh = place(new THREE.Mesh(geometry, material));
    scene.add(mesh);

    // The image: linear radiance in a float target, no tone mapping, no colour-space encoding.
    const target = new THREE.WebGLRenderTarget(width, height, {
        type: THREE.FloatType, format: THREE.RGBAFormat, depthBuffer: true,
        minFilter: THREE.NearestFilter, magFilter: THREE.NearestFilter, generateMipmaps: false,
    });
    renderer.setRenderTarget(target);
    renderer.render(scene, camera);
    const pixels = new Float32Array(4 * width * height);
    renderer.readRenderTargetPixels(target, 0, 0, width, height, pixels);
    renderer.setRenderTarget(null);
    const glError = gl.getError();

    // Frame times: each frame drawn to the canvas and finished (one pixel read back).
    const frames = Number(params.get('frames') || 0);
    const one = new Uint8Array(4);
    const time = () => {
        const times = [];
        renderer.render(scene, camera); // compile and upload outside the timing
        gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, one);
        for (let i = 0; i < frames; ++i) {
            const start = performance.now();
            renderer.render(scene, camera);
            gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, one);
            times.push(performance.now() - start);
        }
        return times;
    };
    const frameMs = { vmf: time() };
    if (frames > 0 && params.get('normal')) {
        const normalMap = await new THREE.TextureLoader().loadAsync(params.get('normal'));
        normalMap.wrapS = normalMap.wrapT = THREE.RepeatWrapping;
        normalMap.colorSpace = THREE.NoColorSpace;
        normalMap.repeat.set(...tiling);
        const standard = new THREE.MeshStandardMaterial({
            color: material.color, roughness: material.roughness, metalness: 0, normalMap,
        });
        mesh.material = standard;
        frameMs.standard = time();
    }

    // Under an environment (three's RoomEnvironment through PMREM) the module's other path: it
    // must compile and add light (no reference image: ndfmip's renderer lights differently).
    mesh.material = material;
    const meanOf = () => {
        renderer.setRenderTarget(target);
        renderer.render(scene, camera);
        const p = new Float32Array(4 * width * height);
        renderer.readRenderTargetPixels(target, 0, 0, width, height, p);
        renderer.setRenderTarget(null);
        let sum = 0;
        for (let i = 0; i < p.length; i += 4) sum += (p[i] + p[i + 1] + p[i + 2]) / 3;
        return sum / (width * height);
    };
    const direct = meanOf();
    scene.environment = new THREE.PMREMGenerator(renderer).fromScene(new RoomEnvironment(), 0.04).texture;
    const withEnvironment = meanOf();
    const environment = {
        meanDirect: direct, meanWithEnvironment: withEnvironment,
        programsRunnable: renderer.info.programs.every(p => !p.diagnostics || p.diagnostics.runnable),
        glError: gl.getError(),
    };

    await post('/result', {
        environment,
        three: THREE.REVISION,
        renderer: gl.getParameter(gl.getExtension('WEBGL_debug_renderer_info') ? 0x9246 : gl.RENDERER),
        width, height, glError, frameMs,
        pixels: base64(new Uint8Array(pixels.buffer)),
    });
}

main().catch(fail);
