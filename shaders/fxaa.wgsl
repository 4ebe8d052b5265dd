// Edges smoothed after the scene is drawn with one sample a pixel (FXAA, after Timothy
// Lottes' fast variant): where the luma of a pixel and its four diagonal neighbours
// spreads, the edge's direction comes from their differences, and the pixel takes the
// average along it (two or four taps), keeping the four-tap average only while it stays
// within the neighbours' range. Flat areas (most of the picture: the background, the
// inside of a part) read five taps and return the pixel as it is.

@group(0) @binding(0) var source: texture_2d<f32>;
@group(0) @binding(1) var source_sampler: sampler;

// A spread of luma below this share of the brightest neighbour, or below the floor, is
// no edge.
const EDGE_THRESHOLD: f32 = 0.125;
const EDGE_FLOOR: f32 = 0.03;
// How far along an edge (pixels) the average reaches, and how the direction's length is
// damped in dark areas.
const SPAN_MAX: f32 = 8.0;
const REDUCE_MUL: f32 = 0.125;
const REDUCE_MIN: f32 = 0.0078125;

// The cells over the surface's edges (`render::fxaa::edge_rects`), in normalized device
// coordinates.
@vertex
fn vs_cells(@location(0) at: vec2<f32>) -> @builtin(position) vec4<f32> {
    return vec4<f32>(at, 0.0, 1.0);
}

// `source` is read through its plain format: the values as stored, in gamma space.
fn luma(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.299, 0.587, 0.114));
}

fn tap(uv: vec2<f32>) -> vec3<f32> {
    return textureSampleLevel(source, source_sampler, uv, 0.0).rgb;
}

// A texel by its integer coordinates (no filtering: cheaper on a software rasterizer).
fn texel_at(at: vec2<i32>, size: vec2<i32>) -> vec4<f32> {
    return textureLoad(source, clamp(at, vec2<i32>(0), size - 1), 0);
}

@fragment
fn fs_fxaa(@builtin(position) at: vec4<f32>) -> @location(0) vec4<f32> {
    let sizei = vec2<i32>(textureDimensions(source));
    let texel = 1.0 / vec2<f32>(sizei);
    let uv = at.xy * texel;
    let p = vec2<i32>(at.xy);
    let m = texel_at(p, sizei);
    let nw = luma(texel_at(p + vec2<i32>(-1, -1), sizei).rgb);
    let ne = luma(texel_at(p + vec2<i32>(1, -1), sizei).rgb);
    let sw = luma(texel_at(p + vec2<i32>(-1, 1), sizei).rgb);
    let se = luma(texel_at(p + vec2<i32>(1, 1), sizei).rgb);
    let lm = luma(m.rgb);
    let lo = min(lm, min(min(nw, ne), min(sw, se)));
    let hi = max(lm, max(max(nw, ne), max(sw, se)));
    if hi - lo < max(EDGE_FLOOR, hi * EDGE_THRESHOLD) {
        return m;
    }
    var dir = vec2<f32>(-((nw + ne) - (sw + se)), (nw + sw) - (ne + se));
    let reduce = max((nw + ne + sw + se) * (0.25 * REDUCE_MUL), REDUCE_MIN);
    let scale = 1.0 / (min(abs(dir.x), abs(dir.y)) + reduce);
    dir = clamp(dir * scale, vec2<f32>(-SPAN_MAX), vec2<f32>(SPAN_MAX)) * texel;
    let a = 0.5 * (tap(uv + dir * (1.0 / 3.0 - 0.5)) + tap(uv + dir * (2.0 / 3.0 - 0.5)));
    let b = a * 0.5 + 0.25 * (tap(uv - dir * 0.5) + tap(uv + dir * 0.5));
    let lb = luma(b);
    if lb < lo || lb > hi {
        return vec4<f32>(a, m.a);
    }
    return vec4<f32>(b, m.a);
}
