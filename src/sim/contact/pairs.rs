//! Which pairs of joint sections the contacts act between.

/// The pairs of joint sections the contacts act between when not every pair: those the
/// pose limit stopped against each other ([`crate::joints::collide::Balls::hold`]). A
/// point pushed out of another part's balls alone, where the pose limit never stopped
/// the two, tore the skin around it: over 25 characters in 10 random poses, contacts
/// between every pair left 10 of 250 poses worse than collision off (an edge up to
/// 5.42×), between these 5 (3.23×; `docs/performance-log.md`, 2026-11-30).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Pairs {
    sections: usize,
    met: Vec<bool>,
}

impl Pairs {
    /// No pair yet, among `sections` sections.
    pub fn new(sections: usize) -> Pairs {
        Pairs {
            sections,
            met: vec![false; sections * sections],
        }
    }

    /// The number of sections.
    pub fn sections(&self) -> usize {
        self.sections
    }

    /// Adds the pair `a`, `b` (either way round); true when it is new.
    pub fn add(&mut self, a: usize, b: usize) -> bool {
        let n = self.sections;
        if a >= n || b >= n || self.met[a * n + b] {
            return false;
        }
        self.met[a * n + b] = true;
        self.met[b * n + a] = true;
        true
    }

    /// Whether `a` and `b` are a pair.
    pub fn has(&self, a: usize, b: usize) -> bool {
        a < self.sections && b < self.sections && self.met[a * self.sections + b]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pairs_go_both_ways_and_ignore_sections_out_of_range() {
        let mut p = Pairs::new(3);
        assert!(!p.has(0, 2));
        assert!(p.add(2, 0));
        assert!(!p.add(0, 2), "already there");
        assert!(p.has(0, 2) && p.has(2, 0) && !p.has(1, 2));
        assert!(!p.add(3, 0) && !p.has(3, 0));
    }
}
