//! Union-find, for the sweep that builds the join tree and the loops of a slice.

/// Union-find with path halving.
pub(crate) struct UnionFind(Vec<u32>);

impl UnionFind {
    pub(crate) fn new(n: usize) -> Self {
        UnionFind((0..n as u32).collect())
    }

    pub(crate) fn find(&mut self, mut x: usize) -> usize {
        while self.0[x] as usize != x {
            self.0[x] = self.0[self.0[x] as usize];
            x = self.0[x] as usize;
        }
        x
    }

    pub(crate) fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.0[ra] = rb as u32;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unions_join_sets_and_nothing_else() {
        let mut set = UnionFind::new(6);
        set.union(0, 1);
        set.union(2, 3);
        set.union(1, 3);
        assert_eq!(set.find(0), set.find(2));
        assert_ne!(set.find(0), set.find(4));
        assert_ne!(set.find(4), set.find(5));
        set.union(3, 0);
        assert_eq!(
            set.find(1),
            set.find(3),
            "a union within a set changes nothing"
        );
        // A long chain is found from its far end.
        let mut chain = UnionFind::new(1000);
        for k in 1..1000 {
            chain.union(k - 1, k);
        }
        assert_eq!(chain.find(0), chain.find(999));
    }
}
