// acuity's shading, shared by the offline pass and scene runs: Lambert plus
// ambient, times vertex colour, times the base-colour texture (a white
// texel for untextured meshes). Both faces are lit. An instance's dither
// range drops the fragments whose 4x4 Bayer threshold at the pixel lies
// outside it (screen-door cross-fades between LODs). An instance's albedo
// (rgb, and 1 in w when set) replaces vertex colour times texture.
struct Frame {
    view_proj: mat4x4<f32>,
    light_dir: vec4<f32>,
    light: vec4<f32>,
};
@group(0) @binding(0) var<uniform> frame: Frame;
@group(1) @binding(0) var base_tex: texture_2d<f32>;
@group(1) @binding(1) var base_smp: sampler;

struct VIn {
    @location(0) pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec3<f32>,
    @location(3) m0: vec4<f32>,
    @location(4) m1: vec4<f32>,
    @location(5) m2: vec4<f32>,
    @location(6) m3: vec4<f32>,
    @location(7) n0: vec4<f32>,
    @location(8) n1: vec4<f32>,
    @location(9) n2: vec4<f32>,
    @location(10) uv: vec2<f32>,
    @location(11) dither: vec2<f32>,
    @location(12) albedo: vec4<f32>,
};
struct VOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) color: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) @interpolate(flat) dither: vec2<f32>,
    @location(4) @interpolate(flat) albedo: vec4<f32>,
};

@vertex
fn vs_main(v: VIn) -> VOut {
    let model = mat4x4<f32>(v.m0, v.m1, v.m2, v.m3);
    let nmat = mat3x3<f32>(v.n0.xyz, v.n1.xyz, v.n2.xyz);
    var o: VOut;
    o.clip = frame.view_proj * (model * vec4<f32>(v.pos, 1.0));
    o.normal = nmat * v.normal;
    o.color = v.color;
    o.uv = v.uv;
    o.dither = v.dither;
    o.albedo = v.albedo;
    return o;
}

@fragment
fn fs_main(i: VOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    // Sampled first: implicit derivatives need uniform control flow.
    let base = textureSample(base_tex, base_smp, i.uv).rgb;
    let t = bayer4(vec2<u32>(i.clip.xy));
    if (t < i.dither.x || t >= i.dither.y) {
        discard;
    }
    var n = normalize(i.normal);
    if (!front) { n = -n; }
    let lambert = max(dot(n, frame.light_dir.xyz), 0.0);
    let surface = mix(i.color * base, i.albedo.rgb, i.albedo.w);
    let c = surface * (frame.light.y + frame.light.x * lambert);
    return vec4<f32>(clamp(c, vec3<f32>(0.0), vec3<f32>(1.0)), 1.0);
}

// The 4x4 ordered-dither threshold of a pixel, in k / 16 for k = 0..15:
// neighbouring thresholds are spread apart, so any fraction of the pixels
// is spread evenly over each 4x4 tile.
fn bayer4(p: vec2<u32>) -> f32 {
    let m = array<u32, 16>(0u, 8u, 2u, 10u, 12u, 4u, 14u, 6u, 3u, 11u, 1u, 9u, 15u, 7u, 13u, 5u);
    return f32(m[(p.y % 4u) * 4u + p.x % 4u]) / 16.0;
}
