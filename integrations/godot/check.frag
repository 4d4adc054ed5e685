// Compile check of the Godot include as GLSL ES 3.00 (the include's text comes first).
uniform vec4 a;
uniform vec4 b;
uniform vec3 l;
uniform vec3 v;
out vec4 colour;

void main() {
    colour = vec4(ndfmipVmfGgx4(a, b, b, a, normalize(l), normalize(v), vec3(0.5), 0.1, vec3(1.0)), 1.0);
}
