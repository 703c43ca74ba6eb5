//! `log` records to Android's logcat (tag `stridekit`), and nothing elsewhere.
//!
//! The engines log through the `log` facade (a caught panic at the boundary as an
//! error, filter decisions at debug level). On Android, `init_android_logging` installs
//! `android_logger` once and sets the level; on every other platform it does nothing
//! and returns `false` (a host application installs its own `log` logger, and Apple
//! platforms are not wired yet).

/// How much stridekit logs (Kotlin `LogLevel.WARN`, Swift `.warn`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, uniffi::Enum)]
pub enum LogLevel {
    Off,
    Error,
    Warn,
    Info,
    Debug,
    Trace,
}

impl From<LogLevel> for log::LevelFilter {
    fn from(l: LogLevel) -> Self {
        match l {
            LogLevel::Off => Self::Off,
            LogLevel::Error => Self::Error,
            LogLevel::Warn => Self::Warn,
            LogLevel::Info => Self::Info,
            LogLevel::Debug => Self::Debug,
            LogLevel::Trace => Self::Trace,
        }
    }
}

/// Send stridekit's log records at `level` and more severe to logcat, tag
/// `stridekit`. Call it once at startup (e.g. `Application.onCreate`); calling it
/// again only changes the level. Returns `true` on Android, `false` elsewhere, where
/// this does nothing at all. (If another library in the process installed a `log`
/// logger first, records go to that logger, at this level.)
#[uniffi::export]
pub fn init_android_logging(level: LogLevel) -> bool {
    #[cfg(target_os = "android")]
    {
        // The logger itself passes everything; the `log` max level filters, so a later
        // call can raise or lower it (android_logger initialises only once).
        android_logger::init_once(
            android_logger::Config::default()
                .with_tag("stridekit")
                .with_max_level(log::LevelFilter::Trace),
        );
        log::set_max_level(level.into());
        true
    }
    #[cfg(not(target_os = "android"))]
    {
        let _ = level;
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_map_to_log_filters() {
        assert_eq!(log::LevelFilter::from(LogLevel::Off), log::LevelFilter::Off);
        assert_eq!(
            log::LevelFilter::from(LogLevel::Warn),
            log::LevelFilter::Warn
        );
        assert_eq!(
            log::LevelFilter::from(LogLevel::Trace),
            log::LevelFilter::Trace
        );
    }

    #[cfg(not(target_os = "android"))]
    #[test]
    fn is_a_no_op_off_android() {
        let before = log::max_level();
        for level in [LogLevel::Trace, LogLevel::Off, LogLevel::Error] {
            assert!(!init_android_logging(level));
            assert_eq!(log::max_level(), before, "the log level is left alone");
        }
    }
}
