// A tiny fragment shader for the shader-artifact toolchain test: a helper function (whose name
// must survive SPIR-V, HLSL and GLSL ES) and a main writing a colour.
uniform float ndfmipTestGain;
in vec2 uv;
out vec4 colour;

vec3 ndfmipTestTint(vec2 p) {
    return vec3(p, 0.5) * ndfmipTestGain;
}

void main() {
    colour = vec4(ndfmipTestTint(uv), 1.0);
}
