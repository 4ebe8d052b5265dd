//! Offscreen rendering on the real GPU stack (Mesa's software Vulkan in CI): the default
//! puppet is drawn into an image and checked for content, shading, overlays, and against a
//! reference image with a tolerance.
//!
//! Regenerate the reference with `PUPPET_BLESS=1 cargo test --release --test render`.

use puppet::render::{render_image, Gpu, Image, SceneRenderer, OFFSCREEN_FORMAT};
use puppet::session::{Camera, Overlays, Session};
use puppet::{Puppet, RigFile};
use std::path::Path;

const W: u32 = 320;
const H: u32 = 240;

fn spot_session(rig: RigFile) -> Session {
    let bytes =
        std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/spot.obj")).unwrap();
    let (mesh, _) = puppet::mesh::parse_obj(&bytes).unwrap();
    Session::new(
        Puppet::build(mesh, rig, puppet::progress::silent()).unwrap(),
        "spot",
    )
}

/// Spot with the example rig's head cut.
fn jaw_session() -> Session {
    let rig = RigFile::load(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/examples/spot-jaw.rig.toml"),
    )
    .unwrap();
    spot_session(rig)
}

fn camera(s: &Session) -> Camera {
    let mut c = Camera::default();
    let (lo, hi) = s.puppet.mesh.bounds();
    c.frame(lo.as_vec3(), hi.as_vec3());
    c
}

/// Background colour as it lands in an sRGB image.
fn background() -> [u8; 3] {
    let enc = |c: f64| {
        let c = if c <= 0.0031308 {
            c * 12.92
        } else {
            1.055 * c.powf(1.0 / 2.4) - 0.055
        };
        (c * 255.0).round() as u8
    };
    let b = puppet::render::BACKGROUND;
    [enc(b.r), enc(b.g), enc(b.b)]
}

fn shot(gpu: &Gpu, r: &mut SceneRenderer, s: &Session, cam: &Camera, o: Overlays) -> Image {
    render_image(gpu, r, &s.view(o), cam, W, H).expect("offscreen render")
}

fn luminance_spread(img: &Image) -> f64 {
    let bg = background();
    let lum: Vec<f64> = img
        .rgba
        .chunks(4)
        .filter(|p| (0..3).any(|k| p[k].abs_diff(bg[k]) > 8))
        .map(|p| 0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64)
        .collect();
    let mean = lum.iter().sum::<f64>() / lum.len().max(1) as f64;
    (lum.iter().map(|l| (l - mean).powi(2)).sum::<f64>() / lum.len().max(1) as f64).sqrt()
}

#[test]
fn the_default_puppet_renders_offscreen_with_shading_and_overlays() {
    let gpu = Gpu::headless()
        .expect("a graphics adapter (scripts/setup.sh installs Mesa's software Vulkan)");
    let mut renderer = SceneRenderer::new(&gpu, OFFSCREEN_FORMAT);
    let session = spot_session(RigFile::default());
    let cam = camera(&session);
    let plain = shot(&gpu, &mut renderer, &session, &cam, Overlays::default());
    assert_eq!((plain.width, plain.height), (W, H));
    let coverage = plain.coverage(background(), 8);
    assert!(
        (0.1..0.9).contains(&coverage),
        "the model covers {coverage:.2} of the image"
    );
    let spread = luminance_spread(&plain);
    assert!(
        spread > 12.0,
        "shading varies over the model (luminance spread {spread:.1})"
    );

    // Nothing changed: the second prepare uploads nothing.
    renderer.prepare(
        &gpu,
        &session.view(Overlays::default()),
        &cam,
        W as f32 / H as f32,
    );
    assert_eq!(renderer.last_uploads, 0, "no upload when nothing changed");

    let overlays = Overlays {
        wireframe: true,
        skeleton: true,
        ..Overlays::default()
    };
    let with = shot(&gpu, &mut renderer, &session, &cam, overlays);
    let diff = with.mean_abs_diff(&plain).unwrap();
    assert!(
        diff > 1.0,
        "overlays change the image (mean difference {diff:.2})"
    );
    let again = shot(&gpu, &mut renderer, &session, &cam, Overlays::default());
    assert!(
        again.mean_abs_diff(&plain).unwrap() < 0.01,
        "overlays off restores the image"
    );

    let reference = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/spot_render.png");
    if bless() {
        plain.save_png(&reference).unwrap();
    }
    let expected = Image::load_png(&reference).expect("reference image tests/data/spot_render.png");
    let d = plain
        .mean_abs_diff(&expected)
        .expect("same size as the reference");
    assert!(
        d < 2.0,
        "differs from the reference by {d:.2} per channel on average"
    );
}

#[test]
fn a_turned_section_shows_in_the_image() {
    let gpu = Gpu::headless().expect("a graphics adapter");
    let mut renderer = SceneRenderer::new(&gpu, OFFSCREEN_FORMAT);
    let mut session = jaw_session();
    let cam = camera(&session);
    let before = shot(&gpu, &mut renderer, &session, &cam, Overlays::default());
    let head = session.puppet.joints.find("head").unwrap();
    session.select(Some(head), false);
    session.rotate_selected(glam::DQuat::from_rotation_x(0.6));
    for _ in 0..30 {
        session.advance(1.0 / 60.0, 1);
    }
    let after = shot(&gpu, &mut renderer, &session, &cam, Overlays::default());
    let diff = after.mean_abs_diff(&before).unwrap();
    assert!(
        diff > 1.0,
        "turning the head changes the picture ({diff:.2})"
    );
}

/// Creases are shaded: Spot with its head turned down onto its chest, drawn with and
/// without the occlusion of its medial balls. With it, the skin in its creases (the neck
/// folded under the head, where the legs meet the body, the ears' roots) is darker, a small
/// share of the puppet, and nothing is lighter; under the studio's lights and under each matcap.
#[test]
fn creases_are_darker_where_the_body_hides_the_sky() {
    let gpu = Gpu::headless().expect("a graphics adapter");
    let mut renderer = SceneRenderer::new(&gpu, OFFSCREEN_FORMAT);
    let mut session = jaw_session();
    let head = session.puppet.joints.find("head").unwrap();
    session.select(Some(head), false);
    session.rotate_selected(glam::DQuat::from_rotation_x(0.6));
    for _ in 0..30 {
        session.advance(1.0 / 60.0, 1);
    }
    let cam = camera(&session);
    for lighting in <puppet::session::Lighting as clap::ValueEnum>::value_variants()
        .iter()
        .copied()
    {
        creases_darker(&gpu, &mut renderer, &session, &cam, lighting);
    }
}

/// [`creases_are_darker_where_the_body_hides_the_sky`] under one lighting.
fn creases_darker(
    gpu: &Gpu,
    renderer: &mut SceneRenderer,
    session: &Session,
    cam: &Camera,
    lighting: puppet::session::Lighting,
) {
    let plain = Overlays {
        pivots: false,
        lighting,
        ..Overlays::default()
    };
    let shaded = shot(gpu, renderer, session, cam, plain);
    let flat = shot(
        gpu,
        renderer,
        session,
        cam,
        Overlays {
            occlusion: false,
            ..plain
        },
    );
    let bg = luminance([background()[0], background()[1], background()[2], 255]);
    let (mut puppet, mut darker, mut lighter) = (0usize, 0usize, 0usize);
    for (a, b) in shaded.rgba.chunks(4).zip(flat.rgba.chunks(4)) {
        let (a, b) = (
            luminance([a[0], a[1], a[2], a[3]]),
            luminance([b[0], b[1], b[2], b[3]]),
        );
        if (b - bg).abs() > 4.0 {
            puppet += 1;
        }
        if a < b - 4.0 {
            darker += 1;
        }
        if a > b + 1.0 {
            lighter += 1;
        }
    }
    assert!(
        darker as f64 > 0.01 * puppet as f64 && (darker as f64) < 0.4 * puppet as f64,
        "{lighting:?}: {darker} of the puppet's {puppet} pixels are darker with creases shaded"
    );
    assert!(
        lighter * 1000 < puppet,
        "{lighting:?}: {lighter} pixels are lighter with creases shaded"
    );
}

/// A matcap lights the surface from the camera: a sphere looks the same from above as from
/// the side under one (its light turns with the eye), where the studio's sky stays above
/// the world and the sphere reads differently; on Spot each matcap keeps the silhouette
/// and gives the surface its own tones (the jelly a near-white highlight the clay lacks).
#[test]
fn a_matcap_lights_the_shape_from_the_camera_in_its_own_tones() {
    use puppet::session::Lighting;
    let gpu = Gpu::headless().expect("a graphics adapter");
    let mut renderer = SceneRenderer::new(&gpu, OFFSCREEN_FORMAT);
    let sphere = Session::new(
        Puppet::build(
            puppet::mesh::shapes::icosphere(1.0, 4),
            RigFile::default(),
            puppet::progress::silent(),
        )
        .unwrap(),
        "sphere",
    );
    let side = camera(&sphere);
    let above = Camera {
        pitch: 1.2,
        yaw: side.yaw + 0.7,
        ..side
    };
    let mean_difference = |a: &Image, b: &Image| {
        a.rgba
            .iter()
            .zip(&b.rgba)
            .map(|(x, y)| x.abs_diff(*y) as f64)
            .sum::<f64>()
            / a.rgba.len() as f64
    };
    let bare = |lighting| Overlays {
        pivots: false,
        ground: false,
        lighting,
        ..Overlays::default()
    };
    let turned: Vec<f64> = <Lighting as clap::ValueEnum>::value_variants()
        .iter()
        .map(|&l| {
            let a = shot(&gpu, &mut renderer, &sphere, &side, bare(l));
            let b = shot(&gpu, &mut renderer, &sphere, &above, bare(l));
            mean_difference(&a, &b)
        })
        .collect();
    let (studio, matcaps) = (turned[0], &turned[1..]);
    assert!(
        matcaps.iter().all(|&m| m < 0.1) && studio > 0.3,
        "the sphere from the side and from above differ by {studio:.2} a channel (over \
         the image) in the studio, {matcaps:.2?} under the matcaps"
    );
    let session = spot_session(RigFile::default());
    let cam = camera(&session);
    let bg = background();
    let is_bg = |p: &[u8]| (0..3).all(|k| p[k].abs_diff(bg[k]) <= 8);
    let shots: Vec<Image> = <Lighting as clap::ValueEnum>::value_variants()
        .iter()
        .map(|&l| shot(&gpu, &mut renderer, &session, &cam, bare(l)))
        .collect();
    let brightest = |img: &Image| {
        img.rgba
            .chunks(4)
            .map(|p| luminance([p[0], p[1], p[2], p[3]]))
            .fold(0.0, f64::max)
    };
    for (k, l) in <Lighting as clap::ValueEnum>::value_variants()
        .iter()
        .enumerate()
        .skip(1)
    {
        let (studio, matcap) = (&shots[0], &shots[k]);
        let outline = studio
            .rgba
            .chunks(4)
            .zip(matcap.rgba.chunks(4))
            .filter(|(a, b)| is_bg(a) != is_bg(b))
            .count();
        let model = studio.rgba.chunks(4).filter(|p| !is_bg(p)).count();
        assert!(
            outline * 100 < model,
            "{l:?}: {outline} of {model} pixels change between background and puppet"
        );
        let d = mean_difference(studio, matcap) * (W * H) as f64 / model as f64;
        assert!(
            d > 4.0,
            "{l:?}: the puppet differs by {d:.2} a channel from the studio's"
        );
        assert!(luminance_spread(matcap) > 10.0, "{l:?} reads flat");
    }
    let (clay, jelly) = (brightest(&shots[1]), brightest(&shots[2]));
    assert!(
        jelly > 235.0 && jelly > clay + 15.0,
        "brightest pixel: jelly {jelly:.0}, clay {clay:.0}"
    );
}

/// The human's elbow bent 90°, seen from above, as a hinge and with the default joint band:
/// the guide's before/after pictures (`docs/images/elbow-90-hinge.png`,
/// `docs/images/elbow-90-band.png`), regenerated with `PUPPET_BLESS=1`.
#[test]
fn the_readme_s_pictures_of_the_bent_elbow() {
    use puppet::puppet::bend::JOINTS;
    let gpu = Gpu::headless().expect("a graphics adapter");
    let mut renderer = SceneRenderer::new(&gpu, OFFSCREEN_FORMAT);
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/meshes/human.obj");
    let mesh = puppet::mesh::load(&path).unwrap().0;
    let elbow = JOINTS[0];
    let mut shots = Vec::new();
    for (band, name) in [(Some(0.0), "hinge"), (None, "band")] {
        let p = elbow
            .bent(&mesh, band, 90.0, puppet::sim::Params::default())
            .unwrap();
        let mut session = Session::new(p, "elbow");
        // The pose the puppet was bent to, so its pivot is drawn where the bend carries it.
        if let Some(child) = session.puppet.joints.find(puppet::puppet::bend::CUT) {
            session.local[child] = elbow.rotation(90.0);
        }
        let mut cam = Camera {
            yaw: 0.6,
            pitch: 1.0,
            ..Camera::default()
        };
        let around = glam::Vec3::new(-0.50, 1.33, 0.0);
        cam.frame(
            around - glam::Vec3::splat(0.14),
            around + glam::Vec3::splat(0.14),
        );
        // A close-up of the skin: the ground far below would only show through.
        let overlays = Overlays {
            ground: false,
            ..Overlays::default()
        };
        let image = render_image(&gpu, &mut renderer, &session.view(overlays), &cam, 480, 360)
            .expect("offscreen render");
        let reference =
            Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("docs/images/elbow-90-{name}.png"));
        if bless() {
            image.save_png(&reference).unwrap();
        }
        let expected = Image::load_png(&reference).expect("the guide's picture");
        let d = image.mean_abs_diff(&expected).expect("same size");
        assert!(
            d < 2.0,
            "{name}: differs from the guide's picture by {d:.2}"
        );
        shots.push(image);
    }
    // The two pictures show different skin.
    assert!(shots[0].mean_abs_diff(&shots[1]).unwrap() > 1.0);
}

/// The guide's picture of Spot's mouth opened about one hinge (`spot-mouth.rig.toml`: the
/// jaw a box cut whose pivot the head shares, the tail's tip a sphere cut), with the cuts
/// and pivots shown: `docs/images/spot-mouth.png`, regenerated with `PUPPET_BLESS=1`.
#[test]
fn the_readme_s_picture_of_a_mouth_opened_about_one_hinge() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let rig = RigFile::load(&root.join("assets/examples/spot-mouth.rig.toml")).unwrap();
    let mut s = spot_session(rig);
    let j = &s.puppet.joints;
    let (head, jaw, tail) = (
        j.find("head").unwrap(),
        j.find("jaw").unwrap(),
        j.find("tail").unwrap(),
    );
    s.local[head] = puppet::joints::Local::axis_angle(glam::DVec3::X, 20.0);
    s.local[jaw] = puppet::joints::Local::axis_angle(-glam::DVec3::X, 40.0);
    s.local[tail] = puppet::joints::Local::axis_angle(glam::DVec3::Y, 30.0);
    let pose = s.puppet.joints.pose(&s.local);
    for _ in 0..240 {
        s.puppet.sim.step(&pose);
    }
    let gpu = Gpu::headless().expect("a graphics adapter");
    let mut renderer = SceneRenderer::new(&gpu, OFFSCREEN_FORMAT);
    let mut cam = Camera {
        yaw: 2.3,
        pitch: 0.1,
        ..Camera::default()
    };
    // The head, from the side and a little ahead.
    cam.frame(
        glam::Vec3::new(-0.3, -0.1, -0.9),
        glam::Vec3::new(0.3, 0.9, 0.1),
    );
    let overlays = Overlays {
        cuts: true,
        pivots: true,
        ..Overlays::default()
    };
    let image = render_image(&gpu, &mut renderer, &s.view(overlays), &cam, 480, 360)
        .expect("offscreen render");
    let reference = root.join("docs/images/spot-mouth.png");
    if bless() {
        image.save_png(&reference).unwrap();
    }
    let expected = Image::load_png(&reference).expect("the guide's picture");
    let d = image.mean_abs_diff(&expected).expect("same size");
    assert!(d < 2.0, "differs from the guide's picture by {d:.2}");
}

/// `PUPPET_BLESS=1` rewrites the reference images from this run; never under CI, where
/// each image would then be compared with itself.
fn bless() -> bool {
    let bless = std::env::var_os("PUPPET_BLESS").is_some();
    assert!(
        !(bless && std::env::var_os("CI").is_some()),
        "PUPPET_BLESS under CI would compare each image with itself"
    );
    bless
}

fn luminance(p: [u8; 4]) -> f64 {
    0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64
}

/// Of the model's pixels at its silhouette (next to the background, with a model pixel
/// on the other side), the share that lies between the background and that inner pixel:
/// partly covered, as anti-aliasing draws them. Without it a silhouette pixel is either
/// the model's or the background's.
fn soft_silhouette(img: &Image) -> f64 {
    let bg = luminance([background()[0], background()[1], background()[2], 255]);
    let is_bg = |x: u32, y: u32| (luminance(img.pixel(x, y)) - bg).abs() < 1.0;
    let (mut edge, mut soft) = (0usize, 0usize);
    for y in 1..img.height - 1 {
        for x in 1..img.width - 1 {
            if is_bg(x, y) {
                continue;
            }
            for (dx, dy) in [(1i32, 0i32), (-1, 0), (0, 1), (0, -1)] {
                let (bx, by) = ((x as i32 + dx) as u32, (y as i32 + dy) as u32);
                let (ix, iy) = ((x as i32 - dx) as u32, (y as i32 - dy) as u32);
                if !is_bg(bx, by) || is_bg(ix, iy) {
                    continue;
                }
                let inner = luminance(img.pixel(ix, iy)) - bg;
                if inner.abs() < 8.0 {
                    continue;
                }
                edge += 1;
                if (luminance(img.pixel(x, y)) - bg) / inner < 0.75 {
                    soft += 1;
                }
                break;
            }
        }
    }
    soft as f64 / edge.max(1) as f64
}

/// Anti-aliasing: the offscreen renderer draws 4 samples a pixel on Mesa's software Vulkan,
/// and its silhouettes are soft where one sample a pixel leaves them stepped; FXAA (the
/// window's while the puppet moves on a software renderer) softens them too.
#[test]
fn silhouettes_are_anti_aliased() {
    let gpu = Gpu::headless().expect("a graphics adapter");
    let session = spot_session(RigFile::default());
    let cam = camera(&session);
    let bare = Overlays {
        ground: false,
        pivots: false,
        ..Overlays::default()
    };
    let mut msaa = SceneRenderer::new(&gpu, OFFSCREEN_FORMAT);
    assert_eq!(msaa.samples(), puppet::render::scene::MSAA);
    let mut one = SceneRenderer::with_samples(&gpu, OFFSCREEN_FORMAT, 1);
    let mut fxaa = SceneRenderer::with_fxaa(&gpu, OFFSCREEN_FORMAT);
    assert!(fxaa.fxaa() && fxaa.samples() == 1);
    let soft = soft_silhouette(&shot(&gpu, &mut msaa, &session, &cam, bare));
    let stepped = soft_silhouette(&shot(&gpu, &mut one, &session, &cam, bare));
    let smoothed = soft_silhouette(&shot(&gpu, &mut fxaa, &session, &cam, bare));
    assert!(
        soft > 0.35 && smoothed > 0.3 && stepped < 0.2,
        "partly covered silhouette pixels: {soft:.2} with 4 samples, {smoothed:.2} with FXAA, \
         {stepped:.2} with one sample"
    );
}

/// FXAA smooths the surface, not the overlays: the cut planes, pivots and skeleton are
/// drawn after it, as crisp as without it (FXAA run over them blurs their one-pixel
/// lines).
#[test]
fn fxaa_leaves_the_overlays_crisp() {
    let gpu = Gpu::headless().expect("a graphics adapter");
    let session = jaw_session();
    let cam = camera(&session);
    let with = Overlays {
        ground: false,
        cuts: true,
        pivots: true,
        skeleton: true,
        ..Overlays::default()
    };
    let without = Overlays {
        cuts: false,
        pivots: false,
        skeleton: false,
        ..with
    };
    let mut fxaa = SceneRenderer::with_fxaa(&gpu, OFFSCREEN_FORMAT);
    let mut one = SceneRenderer::with_samples(&gpu, OFFSCREEN_FORMAT, 1);
    let lines = shot(&gpu, &mut one, &session, &cam, with);
    let bare = shot(&gpu, &mut one, &session, &cam, without);
    let smoothed = shot(&gpu, &mut fxaa, &session, &cam, with);
    // The overlays' pixels: where they changed the one-sample picture.
    let (mut count, mut off) = (0usize, 0.0f64);
    for ((a, b), c) in lines
        .rgba
        .chunks(4)
        .zip(bare.rgba.chunks(4))
        .zip(smoothed.rgba.chunks(4))
    {
        let px = |p: &[u8]| [p[0], p[1], p[2], p[3]];
        if (luminance(px(a)) - luminance(px(b))).abs() > 24.0 {
            count += 1;
            off += (luminance(px(a)) - luminance(px(c))).abs();
        }
    }
    let mean = off / count.max(1) as f64;
    assert!(count > 500, "{count} overlay pixels");
    assert!(
        mean < 4.0,
        "the overlays' pixels differ by {mean:.1} levels of luminance with FXAA"
    );
}

/// The ground: a soft shadow under the puppet, darker than the background (nothing else on
/// the ground is), and gone with the ground; the shadow map is drawn again only when the
/// surface moved.
#[test]
fn the_ground_shows_the_puppet_s_shadow_and_redraws_it_only_when_it_moves() {
    let gpu = Gpu::headless().expect("a graphics adapter");
    let mut renderer = SceneRenderer::new(&gpu, OFFSCREEN_FORMAT);
    let mut session = jaw_session();
    let cam = Camera {
        pitch: 0.6,
        ..camera(&session)
    };
    // (Creases unshaded: a deep one may be darker than the background.)
    let on = Overlays {
        occlusion: false,
        ..Overlays::default()
    };
    let off = Overlays {
        ground: false,
        ..on
    };
    let with = shot(&gpu, &mut renderer, &session, &cam, on);
    let without = shot(&gpu, &mut renderer, &session, &cam, off);
    let bg = luminance([background()[0], background()[1], background()[2], 255]);
    let (mut ground, mut shadow, mut darker_without) = (0usize, 0usize, 0usize);
    for (a, b) in with.rgba.chunks(4).zip(without.rgba.chunks(4)) {
        let (a, b) = ([a[0], a[1], a[2], a[3]], [b[0], b[1], b[2], b[3]]);
        if luminance(b) < bg - 3.0 {
            darker_without += 1;
        }
        // The ground's pixels: where the ground changed the image.
        if (luminance(a) - luminance(b)).abs() > 1.0 {
            ground += 1;
            if luminance(a) < bg - 3.0 {
                shadow += 1;
            }
        }
    }
    let pixels = (W * H) as f64;
    assert!(
        ground as f64 > 0.1 * pixels,
        "the ground covers {ground} pixels"
    );
    assert!(
        shadow as f64 > 0.002 * pixels && shadow < ground / 2,
        "{shadow} of the ground's {ground} pixels are in shadow"
    );
    assert_eq!(
        darker_without, 0,
        "nothing but the shadow is darker than the background"
    );

    // Drawn again: nothing moved, no new shadow map; the head turned, one.
    let passes = renderer.shadow_passes;
    shot(&gpu, &mut renderer, &session, &cam, Overlays::default());
    assert_eq!(renderer.shadow_passes, passes, "nothing moved");
    let head = session.puppet.joints.find("head").unwrap();
    session.select(Some(head), false);
    session.rotate_selected(glam::DQuat::from_rotation_x(0.6));
    session.advance(1.0 / 60.0, 1);
    shot(&gpu, &mut renderer, &session, &cam, Overlays::default());
    assert_eq!(renderer.shadow_passes, passes + 1, "the head turned");
}

/// A closed surface is drawn without its back faces, and looks the same as with them; an
/// open one (a bowl looked into) is drawn with both sides, its inside showing.
#[test]
fn back_faces_are_skipped_only_where_they_never_show() {
    let gpu = Gpu::headless().expect("a graphics adapter");
    let session = spot_session(RigFile::default());
    let cam = camera(&session);
    let mut skipping = SceneRenderer::with_samples(&gpu, OFFSCREEN_FORMAT, 1);
    let mut both = SceneRenderer::with_samples(&gpu, OFFSCREEN_FORMAT, 1);
    both.draw_back_faces(true);
    let a = shot(&gpu, &mut skipping, &session, &cam, Overlays::default());
    let b = shot(&gpu, &mut both, &session, &cam, Overlays::default());
    assert!(skipping.skips_back_faces() && !both.skips_back_faces());
    let d = a.mean_abs_diff(&b).unwrap();
    assert!(d < 0.01, "the closed Spot differs by {d:.3} per channel");

    // A sphere less its top cap, looked into from above: its inside is its back faces.
    let sphere = puppet::mesh::shapes::uv_sphere(1.0, 16, 24);
    let top = |t: &[u32; 3]| t.iter().all(|&v| sphere.positions[v as usize].y > 0.6);
    let kept: Vec<[u32; 3]> = sphere
        .triangles
        .iter()
        .filter(|t| !top(t))
        .copied()
        .collect();
    let mut index = vec![u32::MAX; sphere.positions.len()];
    let mut positions = Vec::new();
    for &v in kept.iter().flatten() {
        if index[v as usize] == u32::MAX {
            index[v as usize] = positions.len() as u32;
            positions.push(sphere.positions[v as usize]);
        }
    }
    let bowl = puppet::mesh::Mesh {
        triangles: kept.iter().map(|t| t.map(|v| index[v as usize])).collect(),
        positions,
    };
    assert!(!bowl.is_closed_outward());
    let session = Session::new(
        Puppet::build(bowl, RigFile::default(), puppet::progress::silent()).unwrap(),
        "bowl",
    );
    let cam = Camera {
        pitch: 1.4,
        ..camera(&session)
    };
    let bare = Overlays {
        ground: false,
        pivots: false,
        ..Overlays::default()
    };
    let mut open = SceneRenderer::with_samples(&gpu, OFFSCREEN_FORMAT, 1);
    let img = shot(&gpu, &mut open, &session, &cam, bare);
    assert!(!open.skips_back_faces());
    // The middle of the image is the bowl's inside (its faces turned away from the eye),
    // seen through the opening: with them skipped it would be the background.
    let bg = background();
    let (mut inside, mut all) = (0, 0);
    for y in H / 2 - 10..H / 2 + 10 {
        for x in W / 2 - 10..W / 2 + 10 {
            let p = &img.rgba[((y * W + x) * 4) as usize..][..3];
            all += 1;
            if (0..3).any(|k| p[k].abs_diff(bg[k]) > 8) {
                inside += 1;
            }
        }
    }
    assert_eq!(
        inside, all,
        "the bowl's inside shows at the middle of the image"
    );
}
