//! The file a replay reads: messages that say what is wrong with a path (missing, a
//! folder, a recording of another kind, and which command replays that kind). The
//! warning for a file cut off mid-write is the CLI's (it prints).

use std::path::Path;

use stridekit_formats::{Content, FormatError};

/// The command that replays a recording of this content, for messages.
pub fn command_for(content: Content) -> Option<&'static str> {
    match content {
        Content::Fit | Content::Tcx | Content::Gpx | Content::ActivityCsv => {
            Some("`stridekit pace`")
        }
        Content::AndroidLog => Some("`stridekit pdr`, `steps` or `orientation`"),
        Content::OxfordAccel => Some("`stridekit steps`"),
        Content::OxfordSteps => Some("`stridekit steps` (given the trace's folder)"),
        Content::Foot(_) => Some("`stridekit foot`"),
        Content::Broad => Some("`stridekit orientation`"),
        Content::Ridi | Content::Ronin => Some("`stridekit odometry`"),
        Content::Unknown => None,
    }
}

/// A reader's error as a message about `path`; `expects` says what the command reads
/// (e.g. "one activity file (.fit, .tcx, .gpx or .csv)").
pub fn read_error(path: &Path, e: FormatError, expects: &str) -> String {
    let p = path.display();
    match e {
        FormatError::Missing => format!("{p}: no such file or folder"),
        FormatError::Folder => format!("{p} is a folder; this command reads {expects}"),
        FormatError::OtherContent { found, .. } => {
            let hint = stridekit_formats::sniff(path)
                .ok()
                .and_then(|s| command_for(s.content))
                .map(|c| format!(": {c} replays it"))
                .unwrap_or_default();
            format!(
                "{p} holds another kind of recording ({found}); this command reads {expects}{hint}"
            )
        }
        other => format!("{p}: {other}"),
    }
}

/// The message for content of another kind than the command reads.
pub fn other_content(path: &Path, content: Content, expects: &str) -> String {
    read_error(
        path,
        FormatError::OtherContent {
            found: content.name(),
            expected: "",
        },
        expects,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_say_what_the_path_is() {
        let p = Path::new("walk");
        assert_eq!(
            read_error(p, FormatError::Missing, "x"),
            "walk: no such file or folder"
        );
        assert!(read_error(p, FormatError::Folder, "one activity file").contains("is a folder"));
        assert_eq!(command_for(Content::Broad), Some("`stridekit orientation`"));
    }
}
