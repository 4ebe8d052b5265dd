// The 3D scene: the puppet's surface and the overlay lines. One file so both pipelines
// share the uniform block that `render::Uniforms` mirrors.
//
// Surface: per-vertex position and normal (uploaded when the simulation moved), per-vertex
// section colour (uploaded when sections or the selection change); a key light, a
// hemispheric ambient and a small specular highlight.
// Lines: wireframe, skeletal points, bone points and springs, cut planes, pivots. `lift`
// pulls depth-tested lines slightly towards the camera so the surface they lie on does not
// hide them.

struct Uniforms {
    view_proj: mat4x4<f32>,
    // xyz: camera position.
    eye: vec4<f32>,
    // xyz: direction towards the key light; w: 1 when the target is not sRGB and the
    // shader must encode gamma itself.
    light: vec4<f32>,
};

@group(0) @binding(0) var<uniform> u: Uniforms;

fn encode(c: vec3<f32>) -> vec3<f32> {
    if (u.light.w > 0.5) {
        return pow(max(c, vec3<f32>(0.0)), vec3<f32>(1.0 / 2.2));
    }
    return c;
}

struct SurfaceIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
};

struct SurfaceOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
};

@vertex
fn vs_surface(v: SurfaceIn) -> SurfaceOut {
    var out: SurfaceOut;
    out.clip = u.view_proj * vec4<f32>(v.position, 1.0);
    out.world = v.position;
    out.normal = v.normal;
    out.color = v.color;
    return out;
}

@fragment
fn fs_surface(f: SurfaceOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    var n = normalize(f.normal);
    if (!front) {
        n = -n;
    }
    let l = normalize(u.light.xyz);
    let view = normalize(u.eye.xyz - f.world);
    let h = normalize(l + view);
    let diffuse = max(dot(n, l), 0.0);
    let hemi = 0.5 + 0.5 * n.y;
    let specular = pow(max(dot(n, h), 0.0), 48.0) * 0.2;
    let c = f.color.rgb * (0.10 + 0.20 * hemi + 0.75 * diffuse) + vec3<f32>(specular);
    return vec4<f32>(encode(c), 1.0);
}

struct LineIn {
    @location(0) position: vec3<f32>,
    @location(1) color: vec4<f32>,
};

struct LineOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) color: vec4<f32>,
};

@vertex
fn vs_lines(v: LineIn) -> LineOut {
    var out: LineOut;
    let clip = u.view_proj * vec4<f32>(v.position, 1.0);
    let lift = 2e-4 * clip.w;
    out.clip = vec4<f32>(clip.xy, clip.z - lift, clip.w);
    out.color = v.color;
    return out;
}

@fragment
fn fs_lines(f: LineOut) -> @location(0) vec4<f32> {
    return vec4<f32>(encode(f.color.rgb), f.color.a);
}
