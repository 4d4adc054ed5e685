// Serves folders over HTTP on 127.0.0.1 only, opens one page in headless chromium (WebGL2 on
// SwiftShader) and waits for the page to POST its result; writes that result to a file, then
// stops the browser and the server. Bounded in time: the browser is killed at the deadline.
//
//   node serve_page.mjs --chromium /usr/bin/chromium --out result.json --timeout 90 \
//       --mount /three/=node_modules/three --mount /engines/=tests/engines --mount /asset/=DIR \
//       --page '/engines/three_page.html?script=three_gltf_levels.mjs&glb=/asset/out.glb'
//
// The page POSTs /result (the JSON to write: exit 0) or /fail (a message: exit 1); anything it
// POSTs to /log is printed. Exit 2: the deadline passed; exit 3: the browser ended first.
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import http from 'node:http';
import os from 'node:os';
import path from 'node:path';

const args = { mount: [] };
for (let i = 2; i < process.argv.length; i += 2) {
    const key = process.argv[i].replace(/^--/, ''), value = process.argv[i + 1];
    if (value === undefined) throw new Error(`${process.argv[i]} needs a value`);
    if (key === 'mount') args.mount.push(value);
    else args[key] = value;
}
for (const key of ['chromium', 'out', 'page'])
    if (!args[key]) throw new Error(`--${key} is required`);
const timeoutMs = 1000 * Number(args.timeout || 90);

const mounts = args.mount.map(m => {
    const at = m.indexOf('=');
    return { prefix: m.slice(0, at), root: path.resolve(m.slice(at + 1)) };
});
const types = {
    '.html': 'text/html', '.js': 'text/javascript', '.mjs': 'text/javascript',
    '.wasm': 'application/wasm', '.json': 'application/json', '.glb': 'model/gltf-binary',
    '.ktx2': 'image/ktx2', '.png': 'image/png',
};

// The file a GET names, or null: only below a mount's root.
function resolve(urlPath) {
    let p;
    try {
        p = decodeURIComponent(urlPath);
    } catch {
        return null;
    }
    if (p.includes('\0')) return null;
    for (const { prefix, root } of mounts) {
        if (!p.startsWith(prefix)) continue;
        const file = path.resolve(root, '.' + path.posix.normalize('/' + p.slice(prefix.length)));
        if (file !== root && !file.startsWith(root + path.sep)) return null;
        return file;
    }
    return null;
}

const started = Date.now();
let browser = null, finished = false, pageAt = 0;
const profile = fs.mkdtempSync(path.join(os.tmpdir(), 'ndfmip-chromium-'));
const browserLog = args.out + '.chromium.log';

function finish(code, message) {
    if (finished) return;
    finished = true;
    if (message) console.error(message);
    clearTimeout(deadline);
    server.close();
    const done = () => {
        fs.rmSync(profile, { recursive: true, force: true });
        process.exit(code);
    };
    if (!browser || browser.exitCode !== null || browser.signalCode !== null) return done();
    browser.once('exit', done);
    try {
        process.kill(-browser.pid, 'SIGTERM'); // the browser and its child processes
    } catch {}
    setTimeout(() => {
        try {
            process.kill(-browser.pid, 'SIGKILL');
        } catch {}
        done();
    }, 5000).unref();
}

function body(request) {
    return new Promise((resolveBody, reject) => {
        const chunks = [];
        request.on('data', c => chunks.push(c));
        request.on('end', () => resolveBody(Buffer.concat(chunks)));
        request.on('error', reject);
    });
}

const server = http.createServer(async (request, response) => {
    const url = new URL(request.url, 'http://127.0.0.1');
    if (request.method === 'POST') {
        const data = await body(request);
        response.writeHead(204).end();
        if (url.pathname === '/log') console.log('page: ' + data.toString());
        else if (url.pathname === '/result') {
            fs.writeFileSync(args.out, data);
            console.log(`result after ${((Date.now() - started) / 1000).toFixed(1)} s`);
            finish(0);
        } else if (url.pathname === '/fail') finish(1, 'the page failed: ' + data.toString());
        return;
    }
    if (!pageAt) {
        pageAt = Date.now();
        console.log(`chromium asked for the page after ${((pageAt - started) / 1000).toFixed(1)} s`);
    }
    const file = resolve(url.pathname);
    if (!file || !fs.existsSync(file) || !fs.statSync(file).isFile()) {
        if (url.pathname !== '/favicon.ico') console.error(`404 ${url.pathname}`);
        response.writeHead(404).end();
        return;
    }
    response.writeHead(200, {
        'Content-Type': types[path.extname(file)] || 'application/octet-stream',
        'Cache-Control': 'no-store',
    });
    fs.createReadStream(file).pipe(response);
});

const deadline = setTimeout(() => {
    let tail = '';
    try {
        tail = fs.readFileSync(browserLog, 'utf8').split('\n').slice(-15).join('\n');
    } catch {}
    finish(2, `no result from the page within ${timeoutMs / 1000} s; chromium's log ends:\n${tail}`);
}, timeoutMs);

server.listen(0, '127.0.0.1', () => {
    const { port } = server.address();
    const log = fs.openSync(browserLog, 'w');
    browser = spawn(args.chromium, [
        '--headless', '--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
        `--user-data-dir=${profile}`, '--no-first-run', '--no-default-browser-check',
        '--disable-extensions', '--disable-background-networking', '--disable-component-update',
        '--disable-sync', '--mute-audio', '--disable-dev-shm-usage', '--window-size=256,256',
        `http://127.0.0.1:${port}${args.page}`,
    ], { detached: true, stdio: ['ignore', log, log] });
    browser.on('exit', (code, signal) => {
        if (finished) return;
        const tail = fs.readFileSync(browserLog, 'utf8').split('\n').slice(-15).join('\n');
        finish(3, `chromium ended (${signal || code}) before the page reported:\n${tail}`);
    });
    browser.on('error', e => finish(3, `chromium did not start: ${e.message}`));
});
