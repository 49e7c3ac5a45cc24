#version 450 core
// Outputs of the view-pass interface (view_pass.h): lit fraction, preview, map index. The
// shadow-volume view writes 0 (shadowed) in the depth draw and, in the second draw, 1 (lit)
// where the pixel's volume count is zero; it uses no maps.

in vec3 v_position;

uniform float u_lit;   // 0: the depth draw; 1: the lit draw, which reads u_count
uniform vec4 u_light;  // relative to the scene's origin
uniform sampler2D u_count;  // per-pixel volume count (R32F, exact integers), the lit draw only
uniform vec4 u_eye;         // relative to the scene's origin; w = 0 for an orthographic viewer
// The drawn instance receives shadows (render::GpuDraw::receives); one that does not is lit
// wherever the side the viewer sees faces the light, as exact visibility counts it.
uniform int u_receives = 1;
uniform int u_casts = 1;  // render::GpuDraw::casts

layout(location = 0) out float o_mask;
layout(location = 1) out vec4 o_preview;
layout(location = 2) out int o_map;

void main() {
    // Derivatives first: they are undefined in a quad after a discard.
    vec3 n = normalize(cross(dFdx(v_position), dFdy(v_position)));
    vec3 to_light = normalize(u_light.xyz - u_light.w * v_position);
    float diffuse = abs(dot(n, to_light));
    vec3 seen = cross(dFdx(v_position), dFdy(v_position));
    if (dot(seen, u_eye.xyz - u_eye.w * v_position) < 0.0) seen = -seen;
    bool faces_light = dot(seen, u_light.xyz - u_light.w * v_position) > 0.0;
    // A receiver is shadowed where a volume holds the pixel; one that casts nothing has no
    // volume of its own over its far side, so there its facing decides too, as exact
    // visibility's does. A non-receiver is lit by its facing alone. A shadowed pixel keeps the
    // depth draw's values. (A caster's own volume holds its far side, so its facing, taken
    // from derivatives and noisier than the count at the terminator, is not asked.)
    // (The count target is read in the lit draw only: the depth draw writes it.)
    bool in_volume = u_lit > 0.5 && texelFetch(u_count, ivec2(gl_FragCoord.xy), 0).r != 0.0;
    bool shadowed = u_receives == 0 ? !faces_light : in_volume || (u_casts == 0 && !faces_light);
    if (u_lit > 0.5 && shadowed) discard;
    float shade = 0.25 + 0.75 * u_lit * diffuse;
    o_mask = u_lit;
    o_preview = vec4(vec3(shade), 1.0);
    o_map = -1;
}
