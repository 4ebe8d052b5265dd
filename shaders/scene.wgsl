// The 3D scene: the puppet's surface, the ground under it and the overlay lines. One file
// so every pipeline shares the uniform block that `render::Uniforms` mirrors.
//
// Surface: per-vertex position, normal and occlusion (uploaded when the simulation moved),
// per-vertex section colour (uploaded when sections or the selection change); studio
// lighting that reads shape: a warm key, a cool fill from the other side, a rim from
// behind, a hemispheric ambient along the world's up and a small specular highlight, the
// ambient, fill and rim dimmed in creases by how much of the sky the body's own medial
// balls hide there (`geom::occlusion`), the key by more than half. Or a matcap
// (`fs_matcap`): light fixed to the camera, read from the normal in the camera's frame.
// Shadow: the surface's depth seen from above along the up (the shadow map), then how dark
// its soft shadow is over the ground (the shade), both drawn only when the surface moved.
// Ground: a square across the up under the puppet, with a faint grid and the puppet's soft
// shadow, darker where a part is near the ground, fading out towards its edge.
// Lines: wireframe, skeletal points, bone points and springs, cut planes, pivots. `lift`
// pulls depth-tested lines slightly towards the camera so the surface they lie on does not
// hide them.

struct Uniforms {
    view_proj: mat4x4<f32>,
    // World to the shadow map's clip space (an orthographic view down the up).
    shadow_proj: mat4x4<f32>,
    // xyz: camera position.
    eye: vec4<f32>,
    // xyz: unit direction towards the key light; w: 1 when the target is not sRGB and the
    // shader must encode gamma itself.
    key: vec4<f32>,
    // xyz: unit, towards the fill light, and towards the rim light.
    fill: vec4<f32>,
    rim: vec4<f32>,
    // xyz: the world's up; w: 1 when the ground is drawn.
    up: vec4<f32>,
    // xyz: the ground's centre; w: half its side.
    ground: vec4<f32>,
    // xyz: the ground's directions across the up; w: the grid's spacing, and the height
    // over which an occluder's shadow fades.
    across_a: vec4<f32>,
    across_b: vec4<f32>,
    // The camera's right and up in the world; the right's w: how much of the matcap's rim
    // takes the part's colour.
    camera_right: vec4<f32>,
    camera_up: vec4<f32>,
    // The matcap's light in the camera's frame (x right, y up, z towards the eye); w: how
    // far its light wraps round the shape.
    matcap_light: vec4<f32>,
    // The matcap's ambient, rim, highlight, and the highlight's exponent.
    matcap_terms: vec4<f32>,
};

@group(0) @binding(0) var<uniform> u: Uniforms;
// The surface's depth seen down the up (written by `vs_shadow`, read by `fs_shade`).
@group(0) @binding(1) var shadow_map: texture_depth_2d;
// How dark the shadow is over the ground (written by `fs_shade`, read by `fs_ground`).
@group(0) @binding(2) var shade: texture_2d<f32>;
@group(0) @binding(3) var shade_sampler: sampler;

fn encode(c: vec3<f32>) -> vec3<f32> {
    if (u.key.w > 0.5) {
        return pow(max(c, vec3<f32>(0.0)), vec3<f32>(1.0 / 2.2));
    }
    return c;
}

struct SurfaceIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
    @location(3) occlusion: f32,
};

struct SurfaceOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
    @location(3) occlusion: f32,
};

@vertex
fn vs_surface(v: SurfaceIn) -> SurfaceOut {
    var out: SurfaceOut;
    out.clip = u.view_proj * vec4<f32>(v.position, 1.0);
    out.world = v.position;
    out.normal = v.normal;
    out.color = v.color;
    out.occlusion = v.occlusion;
    return out;
}

@fragment
fn fs_surface(f: SurfaceOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    var n = normalize(f.normal);
    if (!front) {
        n = -n;
    }
    // The lights' directions come unit (`SceneRenderer::prepare`), and the powers are
    // products: on a software rasterizer a pixel's shading is most of a frame.
    let key = u.key.xyz;
    let view = normalize(u.eye.xyz - f.world);
    let h = normalize(key + view);
    let hemi = 0.5 + 0.5 * dot(n, u.up.xyz);
    // The sky a crease leaves open: the ambient, fill and rim light come from all around,
    // the key from one side, so a crease dims them fully and the key by more than half.
    let open = 1.0 - f.occlusion;
    let ambient = mix(vec3<f32>(0.06, 0.055, 0.05), vec3<f32>(0.17, 0.19, 0.22), hemi);
    let lit = (ambient + vec3<f32>(0.16, 0.19, 0.24) * max(dot(n, u.fill.xyz), 0.0)) * open
        + vec3<f32>(0.72, 0.68, 0.62) * max(dot(n, key), 0.0) * (1.0 - 0.6 * f.occlusion);
    // The rim: a light behind the puppet, seen where the surface turns away from the eye.
    let away = 1.0 - max(dot(n, view), 0.0);
    let edge = away * away * away;
    let rim = edge * smoothstep(-0.3, 0.6, dot(n, u.rim.xyz)) * 0.45 * open;
    // max(n·h, 0)^48 = ((((x^3)^2)^2)^2)^2.
    let x = max(dot(n, h), 0.0);
    var s = x * x * x;
    s = s * s;
    s = s * s;
    s = s * s;
    s = s * s;
    let specular = s * 0.18;
    let c = f.color.rgb * lit + vec3<f32>(0.80, 0.88, 1.0) * rim + vec3<f32>(specular);
    return vec4<f32>(encode(c), 1.0);
}

// A matcap: the shade of a normal as the camera sees it, whatever side of the puppet
// that is. A light from `matcap_light` wrapped round the shape, an ambient, a rim where
// the surface turns away from the eye (white, or the part's own colour: light through
// jelly) and a highlight; creases dim all but the highlight.
@fragment
fn fs_matcap(f: SurfaceOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    var w = normalize(f.normal);
    if (!front) {
        w = -w;
    }
    let right = u.camera_right.xyz;
    let up = u.camera_up.xyz;
    let n = normalize(vec3<f32>(dot(w, right), dot(w, up), dot(w, cross(right, up))));
    let light = u.matcap_light.xyz;
    let wrap = u.matcap_light.w;
    let terms = u.matcap_terms;
    let open = 1.0 - 0.8 * f.occlusion;
    // The light's fall-off eased (smoothstep): a matcap's tones turn over the form, not
    // flat across the side that faces the light.
    let d = clamp((dot(n, light) + wrap) / (1.0 + wrap), 0.0, 1.0);
    let diffuse = terms.x + (1.0 - terms.x) * d * d * (3.0 - 2.0 * d);
    let away = 1.0 - max(n.z, 0.0);
    let rim = terms.y * away * away;
    let tint = mix(vec3<f32>(1.0), f.color.rgb, u.camera_right.w);
    let h = normalize(light + vec3<f32>(0.0, 0.0, 1.0));
    let highlight = terms.z * pow(max(dot(n, h), 0.0), terms.w);
    let c = (f.color.rgb * diffuse + tint * rim) * open + vec3<f32>(highlight);
    return vec4<f32>(encode(c), 1.0);
}

@vertex
fn vs_shadow(@location(0) position: vec3<f32>) -> @builtin(position) vec4<f32> {
    return u.shadow_proj * vec4<f32>(position, 1.0);
}

struct GroundOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
};

@vertex
fn vs_ground(@builtin(vertex_index) i: u32) -> GroundOut {
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, 1.0),
    );
    let c = corners[i];
    let world = u.ground.xyz + (u.across_a.xyz * c.x + u.across_b.xyz * c.y) * u.ground.w;
    var out: GroundOut;
    out.clip = u.view_proj * vec4<f32>(world, 1.0);
    out.world = world;
    return out;
}

// The shade: a fullscreen triangle over a small texture covering the shadow map, each
// texel the share of a disc around it that the surface hides from above, an occluder
// high over the ground counting less than one near it (a contact shadow). Drawn when the
// shadow map is, so the ground reads one filtered texel a pixel.
@vertex
fn vs_fullscreen(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let x = f32(i32(i & 1u) * 4 - 1);
    let y = f32(i32(i >> 1u) * 4 - 1);
    return vec4<f32>(x, y, 0.0, 1.0);
}

// The shade's side in texels (`render::pipelines::SHADE_SIZE`).
const SHADE_SIZE: f32 = 128.0;

// Taps of the shade's soft edge: a disc of 16 points.
const DISC = array<vec2<f32>, 16>(
    vec2<f32>(-0.942, -0.399), vec2<f32>(0.946, -0.769), vec2<f32>(-0.094, -0.929),
    vec2<f32>(0.345, 0.294), vec2<f32>(-0.916, 0.458), vec2<f32>(-0.815, -0.879),
    vec2<f32>(-0.383, 0.277), vec2<f32>(0.975, 0.756), vec2<f32>(0.443, -0.975),
    vec2<f32>(0.537, -0.474), vec2<f32>(-0.265, -0.419), vec2<f32>(0.792, 0.191),
    vec2<f32>(-0.242, 0.998), vec2<f32>(-0.814, 0.915), vec2<f32>(0.200, 0.786),
    vec2<f32>(0.144, -0.141),
);

// The darkness the shadow map's texel at `p` (in texels; off the map, its nearest edge
// texel, where the ground has faded out) casts: none where nothing lies above the ground,
// less for an occluder high over it.
fn casts(p: vec2<f32>, size: vec2<f32>, depth_to_world: f32) -> f32 {
    let q = clamp(vec2<i32>(p), vec2<i32>(0), vec2<i32>(size) - vec2<i32>(1));
    let height = (0.5 - textureLoad(shadow_map, q, 0)) * depth_to_world;
    let dark = 1.0 - 0.6 * clamp(height / u.across_b.w, 0.0, 1.0);
    return select(0.0, dark, height > 1e-3 * u.ground.w);
}

@fragment
fn fs_shade(@builtin(position) at: vec4<f32>) -> @location(0) vec4<f32> {
    let size = vec2<f32>(textureDimensions(shadow_map));
    let scale = size / SHADE_SIZE;
    let c = at.xy * scale;
    // The soft edge's radius: a fortieth of the ground's half side, in texels.
    let r = size.x * 0.5 * (1.0 / 40.0);
    // The ground lies halfway down the map's depth, which spans four half sides (see
    // `render::scene::shadow_proj`).
    let w = 4.0 * u.ground.w;
    // The taps written out one by one: in a loop, the disc indexed by its counter is read
    // from memory on a software rasterizer, which made this pass a seventh of a frame.
    let dark = casts(c + DISC[0] * r, size, w) + casts(c + DISC[1] * r, size, w)
        + casts(c + DISC[2] * r, size, w) + casts(c + DISC[3] * r, size, w)
        + casts(c + DISC[4] * r, size, w) + casts(c + DISC[5] * r, size, w)
        + casts(c + DISC[6] * r, size, w) + casts(c + DISC[7] * r, size, w)
        + casts(c + DISC[8] * r, size, w) + casts(c + DISC[9] * r, size, w)
        + casts(c + DISC[10] * r, size, w) + casts(c + DISC[11] * r, size, w)
        + casts(c + DISC[12] * r, size, w) + casts(c + DISC[13] * r, size, w)
        + casts(c + DISC[14] * r, size, w) + casts(c + DISC[15] * r, size, w);
    return vec4<f32>(dark / 16.0, 0.0, 0.0, 1.0);
}

// How much shadow covers the ground at `world`: 0 none, 1 full.
fn ground_shadow(world: vec3<f32>) -> f32 {
    let p = u.shadow_proj * vec4<f32>(world, 1.0);
    let uv = p.xy / p.w * vec2<f32>(0.5, -0.5) + vec2<f32>(0.5, 0.5);
    if (any(uv < vec2<f32>(0.0)) || any(uv > vec2<f32>(1.0))) {
        return 0.0;
    }
    return textureSampleLevel(shade, shade_sampler, uv, 0.0).r;
}

@fragment
fn fs_ground(f: GroundOut) -> @location(0) vec4<f32> {
    let d = f.world - u.ground.xyz;
    let at = vec2<f32>(dot(d, u.across_a.xyz), dot(d, u.across_b.xyz));
    let fade = 1.0 - smoothstep(0.35, 1.0, length(at) / u.ground.w);
    // A faint grid, one pixel wide whatever the distance.
    let cell = at / u.across_a.w;
    let width = max(fwidth(cell), vec2<f32>(1e-6));
    let line = abs(fract(cell - 0.5) - 0.5) / width;
    let grid = 1.0 - min(min(line.x, line.y), 1.0);
    var c = mix(vec3<f32>(0.055, 0.060, 0.070), vec3<f32>(0.12, 0.13, 0.15), grid * 0.45);
    c = c * (1.0 - 0.85 * ground_shadow(f.world));
    return vec4<f32>(encode(c), fade);
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
