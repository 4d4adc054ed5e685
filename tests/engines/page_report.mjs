// What every test page shares: its result, failure and log POSTed to serve_page.mjs (/result,
// /fail, /log), uncaught errors as failures, console errors and warnings (shader logs, WebGL
// errors) in the test's log, and bytes as base64 for the reports.
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
