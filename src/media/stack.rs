//! Which medium a ray is in: the most recently entered mesh medium not yet exited, else the
//! world medium (see `scene::desc::MediumDesc`).

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MediumStack {
    items: [u32; 8],
    len: u8,
}

impl MediumStack {
    pub fn current(&self, world: Option<u32>) -> Option<u32> {
        if self.len == 0 {
            world
        } else {
            Some(self.items[self.len as usize - 1])
        }
    }

    /// Crossing the boundary of a mesh whose interior is `medium`.
    pub fn cross(&mut self, medium: u32, entering: bool) {
        if entering {
            if (self.len as usize) < self.items.len() {
                self.items[self.len as usize] = medium;
                self.len += 1;
            }
        } else if let Some(i) = self.items[..self.len as usize]
            .iter()
            .rposition(|&m| m == medium)
        {
            self.items.copy_within(i + 1..self.len as usize, i);
            self.len -= 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nested_and_overlapping() {
        let mut s = MediumStack::default();
        assert_eq!(s.current(Some(9)), Some(9));
        s.cross(1, true);
        s.cross(2, true);
        assert_eq!(s.current(None), Some(2));
        s.cross(2, false);
        assert_eq!(s.current(None), Some(1));
        // Overlap: enter 3 inside 1, leave 1 first: still in 3.
        s.cross(3, true);
        s.cross(1, false);
        assert_eq!(s.current(None), Some(3));
        s.cross(3, false);
        assert_eq!(s.current(Some(9)), Some(9));
        s.cross(5, false); // exiting a medium never entered is ignored
        assert_eq!(s.current(None), None);
    }
}
