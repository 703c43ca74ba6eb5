//! Turns fuzz bytes into sample fields. Most draws are plausible values (so the
//! fuzzer reaches deep engine states); a few are the extremes that broke engines
//! before: NaN, infinities, 1e300, 1e-300, values at the input limits, times that
//! repeat, go back, jump or switch to milliseconds / nanoseconds.

/// A cursor over fuzz input; once exhausted every draw returns its nominal value.
pub struct Bytes<'a> {
    data: &'a [u8],
    pos: usize,
}

impl<'a> Bytes<'a> {
    pub fn new(data: &'a [u8]) -> Self {
        Self { data, pos: 0 }
    }

    pub fn is_empty(&self) -> bool {
        self.pos >= self.data.len()
    }

    pub fn u8(&mut self) -> u8 {
        let b = self.data.get(self.pos).copied().unwrap_or(0);
        self.pos += 1;
        b
    }

    /// Consumes the next byte if it is `v`.
    pub fn take_if(&mut self, v: u8) -> bool {
        let hit = self.data.get(self.pos) == Some(&v);
        if hit {
            self.pos += 1;
        }
        hit
    }

    fn u16(&mut self) -> u16 {
        u16::from_le_bytes([self.u8(), self.u8()])
    }

    fn raw_f64(&mut self) -> f64 {
        let mut b = [0u8; 8];
        for x in &mut b {
            *x = self.u8();
        }
        f64::from_le_bytes(b)
    }

    pub fn bool(&mut self) -> bool {
        self.u8() & 1 == 1
    }

    /// A value around `center` (spread ±4 `scale`) most of the time, else an extreme.
    pub fn value(&mut self, center: f64, scale: f64) -> f64 {
        if self.is_empty() {
            return center;
        }
        match self.u8() {
            0..=199 => center + scale * 4.0 * (f64::from(self.u16()) / 32768.0 - 1.0),
            200..=209 => 0.0,
            210 => f64::NAN,
            211 => f64::INFINITY,
            212 => f64::NEG_INFINITY,
            213 => 1e300,
            214 => -1e300,
            215 => 1e-300,
            216 => -1e-160,
            // Around the input layer's limits (accel 2000 m/s², gyro 200 rad/s, mag
            // 5000 µT, times 1e11 s) and the magnitudes of other units.
            217 => 1999.999,
            218 => 2000.001,
            219 => 199.999,
            220 => 200.001,
            221 => 5000.001,
            222 => 1e11,
            223 => center * 1e3,
            224 => center * 1e9,
            225 => center / 9.80665,
            226..=239 => scale * 10f64.powi(i32::from(self.u8() % 40) - 20),
            _ => self.raw_f64(),
        }
    }

    /// A 3-vector of `value`s.
    pub fn vec3(&mut self, center: [f64; 3], scale: f64) -> [f64; 3] {
        [
            self.value(center[0], scale),
            self.value(center[1], scale),
            self.value(center[2], scale),
        ]
    }

    /// The next time after `*t` at a nominal interval `dt_s`: mostly regular with
    /// jitter, sometimes repeated, backwards, a gap, a jump, or a unit change. `*t`
    /// follows finite results only.
    pub fn time(&mut self, t: &mut f64, dt_s: f64) -> f64 {
        let next = match self.u8() {
            0..=219 => *t + dt_s * (1.0 + 0.2 * (f64::from(self.u8()) / 128.0 - 1.0)),
            220..=227 => *t,
            228..=233 => *t - dt_s * f64::from(self.u8()),
            234..=239 => *t + f64::from(self.u16()) * 0.05,
            240..=242 => *t * 1e3,
            243..=245 => *t * 1e9,
            246 => *t + 3.1e7,
            247 => f64::NAN,
            248 => f64::INFINITY,
            249 => 2.8e14,
            _ => self.raw_f64(),
        };
        if next.is_finite() {
            *t = next;
        }
        next
    }

    /// Text from the rest of the input (invalid UTF-8 replaced).
    pub fn rest_text(&mut self) -> String {
        let s = String::from_utf8_lossy(&self.data[self.pos.min(self.data.len())..]).into_owned();
        self.pos = self.data.len();
        s
    }
}
