// Overlays drawn as coloured line segments: wireframe, skeletal points, bone points and
// springs, cut planes, pivots. `lift` pulls depth-tested overlays slightly towards the
// camera so they are not hidden by the surface they lie on.

struct Uniforms {
    view_proj: mat4x4<f32>,
    eye: vec4<f32>,
    light: vec4<f32>,
};

@group(0) @binding(0) var<uniform> u: Uniforms;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) color: vec4<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) color: vec4<f32>,
};

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    var out: VertexOut;
    let clip = u.view_proj * vec4<f32>(v.position, 1.0);
    out.clip = vec4<f32>(clip.xy, clip.z - 2e-4 * clip.w, clip.w);
    out.color = v.color;
    return out;
}

@fragment
fn fs_main(f: VertexOut) -> @location(0) vec4<f32> {
    var c = f.color.rgb;
    if (u.light.w > 0.5) {
        c = pow(max(c, vec3<f32>(0.0)), vec3<f32>(1.0 / 2.2));
    }
    return vec4<f32>(c, f.color.a);
}
