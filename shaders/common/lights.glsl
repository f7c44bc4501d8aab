// lights.glsl — the light model; identical to light_intensity() in
// src/scene.c, which the path tracer uses. Change both together.

// Radiant intensity (W/sr) toward unit direction `dir` (from the light out).
vec3 light_intensity(GpuLight l, vec3 dir)
{
    int type = int(l.position_type.w);
    float c = dot(dir, l.direction_width.xyz);
    if (type == LIGHT_SPOT)
        return l.color.rgb * smoothstep(l.spot.x, l.spot.y, c);
    if (type == LIGHT_QUAD)
        return l.color.rgb * max(c, 0.0); // L·A·cosθ
    return l.color.rgb;                  // point
}

// Irradiance at x with normal n (unshadowed) and the unit direction to the light.
vec3 light_irradiance(GpuLight l, vec3 x, vec3 n, out vec3 to_light)
{
    if (int(l.position_type.w) == LIGHT_DIRECTIONAL) {
        to_light = -l.direction_width.xyz;
        return l.color.rgb * max(dot(n, to_light), 0.0);
    }
    vec3 d = l.position_type.xyz - x;
    float d2 = max(dot(d, d), 1e-12);
    to_light = d * inversesqrt(d2);
    return light_intensity(l, -to_light) * max(dot(n, to_light), 0.0) / d2;
}
