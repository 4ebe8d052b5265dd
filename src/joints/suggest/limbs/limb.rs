//! A limb: a suggested cut before it is applied and named (stage 3's output).

use glam::DVec3;

/// A suggested cut before it is named.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Limb {
    /// The cut below it (index in the list), `None` for one on the root.
    pub(crate) parent: Option<usize>,
    /// How many vertices lie past it in the join tree: a plane that takes far more has
    /// slipped past the limb into the body.
    pub(crate) expected: usize,
    /// The size ([`crate::joints::suggest::body::Tree::size`]) of its ring.
    pub(crate) width: f64,
    pub(crate) point: DVec3,
    pub(crate) normal: DVec3,
    pub(crate) pivot: DVec3,
    /// How much deeper its pivot goes when it turns out to be a shoulder or a hip (named
    /// in step 5): [`crate::joints::suggest::rules::SOCKET`] of its root ring's radius for a limb thinner than the core
    /// (whose pivot went in from the cut), else 0.
    pub(crate) socket: f64,
    /// The segment it cuts and the level of `g` it cuts at (`None` for a cut across a
    /// slice of the body: the core at a neck, a waist).
    pub(crate) past: Option<(usize, f64)>,
}

impl Limb {
    /// A cut of the root across a slice of the body of size `width` (a neck across the
    /// core, a waist), not at a level of `g`, with `expected` vertices past it.
    pub(crate) fn across(
        point: DVec3,
        normal: DVec3,
        pivot: DVec3,
        width: f64,
        expected: usize,
    ) -> Limb {
        Limb {
            parent: None,
            expected,
            width,
            socket: 0.0,
            point,
            normal,
            pivot,
            past: None,
        }
    }
}

/// Puts `neck`, a cut across the body, first in `limbs` (parent-first, indexed by
/// position): what hangs from the body past it hangs from it.
pub(crate) fn put_first(limbs: &mut Vec<Limb>, neck: Limb) {
    for limb in limbs.iter_mut() {
        limb.parent = match limb.parent {
            Some(p) => Some(p + 1),
            None if (limb.point - neck.point).dot(neck.normal) > 0.0 => Some(0),
            None => None,
        };
    }
    limbs.insert(0, neck);
}

/// Orders `limbs` parent-first again (a parent moved after its children), keeping their
/// order otherwise: each limb comes at its first chance once its parent has.
pub(crate) fn parents_first(limbs: &mut Vec<Limb>) {
    let n = limbs.len();
    let mut at = vec![usize::MAX; n];
    let mut order = Vec::with_capacity(n);
    while order.len() < n {
        let before = order.len();
        for i in 0..n {
            if at[i] == usize::MAX && limbs[i].parent.is_none_or(|p| at[p] != usize::MAX) {
                at[i] = order.len();
                order.push(i);
            }
        }
        if order.len() == before {
            // A loop of parents (none is made here): leave the rest as they are.
            for (i, a) in at.iter_mut().enumerate() {
                if *a == usize::MAX {
                    *a = order.len();
                    order.push(i);
                }
            }
            break;
        }
    }
    let mut out: Vec<Limb> = order.iter().map(|&i| limbs[i]).collect();
    for l in &mut out {
        l.parent = l.parent.map(|p| at[p]);
    }
    *limbs = out;
}
