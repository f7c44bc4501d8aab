// gi/vpl/falloff.glsl — the distance falloff of a VPL, 1/d², with the notes'
// optional near clamp 1/max(d², c) (u_vpl.near_clamp = c, 0 = off: the clamp
// removes hot spots next to VPLs but biases the result).
float vpl_falloff(float d2)
{
    return 1.0 / max(d2, max(u_vpl.near_clamp, 1e-12));
}

// Φ/π · cosθ_p · cosθ_x (the VPL's radiant intensity toward x times the
// receiver cosine), and the squared distance.
vec3 vpl_intensity_cos(GpuVpl v, vec3 x, vec3 n, out float d2)
{
    vec3 d = x - v.position_xi.xyz;
    d2 = max(dot(d, d), 1e-12);
    float inv = inversesqrt(d2);
    float c = max(0.0, dot(v.normal.xyz, d) * inv) * max(0.0, -dot(n, d) * inv);
    return v.flux.rgb * (c / PI);
}
