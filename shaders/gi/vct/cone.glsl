// gi/vct/cone.glsl — cone tracing through the voxel volume (Crassin et al.
// 2011, §5): front-to-back accumulation of premultiplied radiance and
// opacity, sampling the mip whose voxel equals the cone's diameter there,
// with the isotropic chain or the six directional volumes (weighted by the
// squared direction components, the three facing the cone) above mip 0.
// A sample's opacity stands for a path of one voxel of its mip; a step of
// `step` diameters corrects it to 1 − (1 − α)^step (and scales the
// radiance with it).
layout(binding = TEX_VCT_RADIANCE) uniform sampler3D u_radiance;
layout(binding = TEX_VCT_ANISO + 0) uniform sampler3D u_aniso_px;
layout(binding = TEX_VCT_ANISO + 1) uniform sampler3D u_aniso_nx;
layout(binding = TEX_VCT_ANISO + 2) uniform sampler3D u_aniso_py;
layout(binding = TEX_VCT_ANISO + 3) uniform sampler3D u_aniso_ny;
layout(binding = TEX_VCT_ANISO + 4) uniform sampler3D u_aniso_pz;
layout(binding = TEX_VCT_ANISO + 5) uniform sampler3D u_aniso_nz;

vec4 vct_sample(vec3 uvw, float mip, vec3 d)
{
    if (u_vct.aniso == 0 || mip <= 0.0)
        return textureLod(u_radiance, uvw, mip);
    vec3 w = d * d;
    float lod = max(mip - 1.0, 0.0);
    vec4 a = w.x * (d.x >= 0.0 ? textureLod(u_aniso_px, uvw, lod) : textureLod(u_aniso_nx, uvw, lod)) +
             w.y * (d.y >= 0.0 ? textureLod(u_aniso_py, uvw, lod) : textureLod(u_aniso_ny, uvw, lod)) +
             w.z * (d.z >= 0.0 ? textureLod(u_aniso_pz, uvw, lod) : textureLod(u_aniso_nz, uvw, lod));
    return mip < 1.0 ? mix(textureLod(u_radiance, uvw, 0.0), a, mip) : a;
}

// Traces a cone from p along unit d with tan(half-angle) `tan_half`,
// starting at distance t0 (m). Returns the radiance gathered (rgb) and the
// opacity (a); `occlusion` gets the opacity met within u_vct.ao_range.
vec4 vct_cone(vec3 p, vec3 d, float tan_half, float t0, out float occlusion)
{
    float voxel = u_vct.origin.w;
    float extent = voxel * float(u_vct.size);
    float max_mip = float(u_vct.levels - 1);
    vec3 c = vec3(0.0);
    float a = 0.0;
    occlusion = 0.0;
    float t = t0;
    for (int i = 0; i < 4096 && a < 0.99 && t < u_vct.max_distance; i++) {
        float diameter = max(voxel, 2.0 * t * tan_half);
        float mip = log2(diameter / voxel);
        if (mip > max_mip)
            break;
        vec3 uvw = (p + d * t - u_vct.origin.xyz) / extent;
        if (any(lessThan(uvw, vec3(0.0))) || any(greaterThan(uvw, vec3(1.0))))
            break;
        vec4 s = vct_sample(uvw, mip, d);
        if (s.a > 0.0) {
            float sa = 1.0 - pow(max(1.0 - s.a, 0.0), u_vct.step);
            c += (1.0 - a) * s.rgb * (sa / s.a);
            if (t < u_vct.ao_range)
                occlusion += (1.0 - occlusion) * sa;
            a += (1.0 - a) * sa;
        }
        t += u_vct.step * diameter;
    }
    return vec4(c, a);
}

// Irradiance E (W/m²) at p with unit normal n from the diffuse cone set:
// Σ w_i L_i, w_i = ∫cosθ dω over cone i's cell of the hemisphere (Σ w_i =
// π). `visibility` gets 1 − the cosine-weighted occlusion.
vec3 vct_irradiance(vec3 p, vec3 n, float t0, out float visibility)
{
    vec3 t, b;
    basis(n, t, b);
    vec3 e = vec3(0.0);
    float occluded = 0.0;
    for (int i = 0; i < u_vct.cones; i++) {
        vec3 cd = u_vct.cone[i].xyz;
        vec3 d = normalize(t * cd.x + b * cd.y + n * cd.z);
        float occ;
        vec4 l = vct_cone(p, d, u_vct.cone_aperture[i].x, t0, occ);
        e += u_vct.cone[i].w * l.rgb;
        occluded += u_vct.cone[i].w / PI * occ;
    }
    visibility = 1.0 - occluded;
    return e;
}
