// Loads ?glb= with three.js's GLTFLoader and KTX2Loader (the Basis transcoder served from the
// local three package), once per transcode target in ?targets= (default `auto`), finds the
// material with a normal map and reports what three made of its normalMap and roughnessMap:
// where each came from, its mip levels, and every level read back from the GPU (texelFetch of
// level k into an RGBA8 target, readPixels, rows from the top of the file as in the KTX2).
// POSTs the report to /result (or the error to /fail).
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { KTX2Loader } from 'three/addons/loaders/KTX2Loader.js';

import { base64, fail, levelFetchQuad, post } from './page_report.mjs';

async function main() {
    const params = new URLSearchParams(location.search);
    const canvas = document.createElement('canvas');
    canvas.width = canvas.height = 16;
    document.body.appendChild(canvas);
    const renderer = new THREE.WebGLRenderer({ canvas, antialias: false });
    const gl = renderer.getContext();
    // One level of a texture, exactly: texelFetch into an RGBA8 target of the level's size.
    const target = new THREE.WebGLRenderTarget(1, 1, {
        type: THREE.UnsignedByteType, format: THREE.RGBAFormat, depthBuffer: false,
        minFilter: THREE.NearestFilter, magFilter: THREE.NearestFilter, generateMipmaps: false,
    });
    const quad = levelFetchQuad(null, 0);
    const fetchLevel = quad.material;
    const scene = new THREE.Scene();
    scene.add(quad);
    const camera = new THREE.OrthographicCamera();

    const formats = {};
    for (const [name, value] of Object.entries(THREE))
        if (typeof value === 'number' && /Format$/.test(name) && !(value in formats)) formats[value] = name;

    function describe(texture) {
        const t = {
            mimeType: texture.userData.mimeType || null,
            compressed: !!texture.isCompressedTexture,
            generateMipmaps: texture.generateMipmaps,
            format: formats[texture.format] || String(texture.format),
            colorSpace: texture.colorSpace,
            flipY: texture.flipY,
            width: texture.image.width,
            height: texture.image.height,
            mipmaps: texture.mipmaps.map(m => [m.width, m.height]),
            levels: [],
        };
        fetchLevel.uniforms.map.value = texture;
        const readStart = performance.now();
        texture.mipmaps.forEach((m, k) => {
            target.setSize(m.width, m.height);
            fetchLevel.uniforms.level.value = k;
            renderer.setRenderTarget(target);
            renderer.render(scene, camera);
            const pixels = new Uint8Array(4 * m.width * m.height);
            renderer.readRenderTargetPixels(target, 0, 0, m.width, m.height, pixels);
            t.levels.push(base64(pixels));
        });
        renderer.setRenderTarget(null);
        t.readMs = performance.now() - readStart;
        return t;
    }

    // Each transcode target three can pick: `auto` is what KTX2Loader.detectSupport picks on
    // this browser; the others force one (as on a device that has only it), `rgba` the
    // uncompressed fallback of a device with none.
    const flags = {
        astc: 'astcSupported', bptc: 'bptcSupported', etc2: 'etc2Supported',
        dxt: 'dxtSupported', rgba: null,
    };
    const runs = [];
    for (const target of (params.get('targets') || 'auto').split(',')) {
        const ktx2 = new KTX2Loader()
            .setTranscoderPath('/three/examples/jsm/libs/basis/')
            .detectSupport(renderer);
        if (target !== 'auto') {
            if (!(target in flags)) throw new Error(`unknown transcode target ${target}`);
            for (const key of Object.keys(ktx2.workerConfig)) ktx2.workerConfig[key] = false;
            if (flags[target]) ktx2.workerConfig[flags[target]] = true;
        }
        const loader = new GLTFLoader().setKTX2Loader(ktx2);
        const start = performance.now();
        const gltf = await loader.loadAsync(params.get('glb'));
        const loadMs = performance.now() - start;
        let material = null;
        gltf.scene.traverse(o => {
            if (o.isMesh && o.material && o.material.normalMap && !material) material = o.material;
        });
        if (!material) throw new Error('no mesh with a normalMap in the GLB');
        runs.push({
            target,
            loadMs,
            material: material.name,
            type: material.type,
            metalnessIsRoughness: material.metalnessMap === material.roughnessMap,
            normalMap: describe(material.normalMap),
            roughnessMap: material.roughnessMap ? describe(material.roughnessMap) : null,
            glError: gl.getError(),
        });
        for (const map of [material.normalMap, material.roughnessMap]) if (map) map.dispose();
        ktx2.dispose();
    }

    const extensions = ['WEBGL_compressed_texture_astc', 'EXT_texture_compression_bptc',
                        'WEBGL_compressed_texture_etc', 'WEBGL_compressed_texture_s3tc']
                           .filter(e => gl.getExtension(e));
    await post('/result', {
        three: THREE.REVISION,
        renderer: gl.getParameter(gl.getExtension('WEBGL_debug_renderer_info') ? 0x9246 : gl.RENDERER),
        extensions,
        runs,
    });
}

main().catch(fail);
