/// A fixed-capacity ring buffer on the stack: pushing beyond capacity drops the oldest.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ring<T: Copy + Default, const N: usize> {
    buf: [T; N],
    head: usize,
    len: usize,
}

impl<T: Copy + Default, const N: usize> Default for Ring<T, N> {
    fn default() -> Self {
        Self {
            buf: [T::default(); N],
            head: 0,
            len: 0,
        }
    }
}

impl<T: Copy + Default, const N: usize> Ring<T, N> {
    pub const CAPACITY: usize = N;

    pub fn new() -> Self {
        Self::default()
    }
    pub fn len(&self) -> usize {
        self.len
    }
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
    pub fn clear(&mut self) {
        self.len = 0;
        self.head = 0;
    }
    /// Append, dropping the oldest element when full.
    pub fn push(&mut self, v: T) {
        let idx = (self.head + self.len) % N;
        self.buf[idx] = v;
        if self.len < N {
            self.len += 1;
        } else {
            self.head = (self.head + 1) % N;
        }
    }
    /// Remove and return the oldest element.
    pub fn pop_front(&mut self) -> Option<T> {
        if self.len == 0 {
            return None;
        }
        let v = self.buf[self.head];
        self.head = (self.head + 1) % N;
        self.len -= 1;
        Some(v)
    }
    /// Remove and return the newest element.
    pub fn pop_back(&mut self) -> Option<T> {
        if self.len == 0 {
            return None;
        }
        self.len -= 1;
        Some(self.buf[(self.head + self.len) % N])
    }
    /// Mutable access to the newest element.
    pub fn newest_mut(&mut self) -> Option<&mut T> {
        if self.len == 0 {
            return None;
        }
        Some(&mut self.buf[(self.head + self.len - 1) % N])
    }
    /// Element `i` counted from the oldest (0) to the newest (len − 1).
    pub fn get(&self, i: usize) -> Option<T> {
        (i < self.len).then(|| self.buf[(self.head + i) % N])
    }
    /// Mutable access to element `i` counted back from the newest (0 = newest).
    pub fn back_mut(&mut self, i: usize) -> Option<&mut T> {
        if i < self.len {
            Some(&mut self.buf[(self.head + self.len - 1 - i) % N])
        } else {
            None
        }
    }
    /// Element `i` counted back from the newest (0 = newest).
    pub fn back(&self, i: usize) -> Option<T> {
        (i < self.len).then(|| self.buf[(self.head + self.len - 1 - i) % N])
    }
    pub fn newest(&self) -> Option<T> {
        self.back(0)
    }
    /// Iterate from oldest to newest.
    pub fn iter(&self) -> impl DoubleEndedIterator<Item = T> + '_ {
        (0..self.len).map(move |i| self.buf[(self.head + i) % N])
    }
}

#[cfg(test)]
mod tests {
    use super::Ring;

    #[test]
    fn wraps_and_orders() {
        let mut r: Ring<u32, 3> = Ring::new();
        for v in 1..=5 {
            r.push(v);
        }
        assert_eq!(r.iter().collect::<Vec<_>>(), vec![3, 4, 5]);
        assert_eq!(r.newest(), Some(5));
        assert_eq!(r.back(2), Some(3));
        assert_eq!(r.back(3), None);
        assert_eq!(r.get(0), Some(3));
        assert_eq!(r.pop_front(), Some(3));
        *r.newest_mut().unwrap() = 9;
        assert_eq!(r.iter().collect::<Vec<_>>(), vec![4, 9]);
    }
}
