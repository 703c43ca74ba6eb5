//! Helpers shared by the TCX and GPX readers: document parsing, element lookup by local
//! name (namespace prefixes vary between exporters), numbers and ISO 8601 times.

use chrono::{DateTime, NaiveDateTime};
use roxmltree::{Document, Node};

use crate::record::{finish_counted, Cleanup, Record};
use crate::FormatError;

/// Parses an XML document. A byte-order mark or whitespace before the XML declaration (a
/// known quirk of some Garmin Connect exports) is tolerated.
pub(crate) fn parse<'a>(text: &'a str, format: &'static str) -> Result<Document<'a>, FormatError> {
    let text = text.trim_start_matches('\u{feff}').trim_start();
    Document::parse(text).map_err(|e| FormatError::parse(format, e.to_string()))
}

/// A document cut off mid-write (a watch or app that stopped while saving): the text up
/// to the end of the last complete `<tag>` element (local name, any prefix), with the
/// elements still open there closed, so it parses. `None` when there is no complete
/// `<tag>` or the tags before it do not nest. Comments, CDATA, processing instructions
/// and declarations are skipped; quoted attribute values may hold `>`.
pub(crate) fn close_after_last(text: &str, tag: &str) -> Option<String> {
    // Two linear passes: where the last complete `tag` ends, then which elements are
    // open there (no copy of the open-element stack per element).
    let (cut, _) = scan_tags(text, tag)?;
    let cut = cut?;
    let (_, open) = scan_tags(&text[..cut], tag)?;
    let mut out = String::with_capacity(cut + 16 * open.len());
    out.push_str(&text[..cut]);
    for name in open.iter().rev() {
        out.push_str("</");
        out.push_str(name);
        out.push('>');
    }
    Some(out)
}

/// Tokenises the tags of `text`: the end of the last `</…tag>` (local name) and the
/// elements open at the end of the text. `None` when end tags do not nest.
fn scan_tags<'t>(text: &'t str, tag: &str) -> Option<(Option<usize>, Vec<&'t str>)> {
    let bytes = text.as_bytes();
    let mut stack: Vec<&str> = Vec::new();
    let mut last_end = None;
    let mut i = 0;
    while let Some(off) = text[i..].find('<') {
        let start = i + off;
        let rest = &text[start..];
        let skip_to = |end: &str| rest.find(end).map(|k| start + k + end.len());
        let special = if rest.starts_with("<?") {
            Some("?>")
        } else if rest.starts_with("<!--") {
            Some("-->")
        } else if rest.starts_with("<![CDATA[") {
            Some("]]>")
        } else if rest.starts_with("<!") {
            Some(">")
        } else {
            None
        };
        if let Some(end) = special {
            match skip_to(end) {
                Some(k) => i = k,
                None => break, // the text ends inside it
            }
            continue;
        }
        // A start or end tag: its '>' outside quotes.
        let mut k = start + 1;
        let mut quote = None;
        while k < bytes.len() {
            match (quote, bytes[k]) {
                (None, b'"' | b'\'') => quote = Some(bytes[k]),
                (Some(q), c) if c == q => quote = None,
                (None, b'>') => break,
                _ => {}
            }
            k += 1;
        }
        if k >= bytes.len() {
            break; // the text ends inside this tag
        }
        let inner = &text[start + 1..k];
        i = k + 1;
        if let Some(name) = inner.strip_prefix('/') {
            let name = name.trim();
            if stack.pop() != Some(name) {
                return None;
            }
            if name.rsplit(':').next() == Some(tag) {
                last_end = Some(i);
            }
        } else if !inner.ends_with('/') {
            let name = inner.split(char::is_whitespace).next().unwrap_or("");
            if name.is_empty() {
                return None;
            }
            stack.push(name);
        }
    }
    Some((last_end, stack))
}

/// The records of a track document (TCX, GPX): every `point` element (local name)
/// under a root named `root`, each read by `read` (`None`: skipped), then the clean-up
/// every reader applies. A document cut off mid-write is read up to its last complete
/// `point` ([`close_after_last`]) and says so in [`Cleanup::truncated`].
pub(crate) fn read_track_points(
    text: &str,
    format: &'static str,
    root: &str,
    point: &'static str,
    read: impl Fn(Node) -> Result<Option<Record>, FormatError>,
) -> Result<(Vec<Record>, Cleanup), FormatError> {
    let repaired;
    let mut truncated = false;
    let doc = match parse(text, format) {
        Ok(doc) => doc,
        Err(e) => match close_after_last(text, point) {
            Some(t) => {
                repaired = t;
                truncated = true;
                parse(&repaired, format).map_err(|_| e)?
            }
            None => return Err(e),
        },
    };
    expect_root(&doc, root, format)?;
    let mut records = Vec::new();
    for node in elements(doc.root_element(), point) {
        if let Some(record) = read(node)? {
            records.push(record);
        }
    }
    let (records, mut cleanup) = finish_counted(records)?;
    cleanup.truncated = truncated;
    Ok((records, cleanup))
}

/// Checks the local name of the root element.
pub(crate) fn expect_root(
    doc: &Document,
    name: &str,
    format: &'static str,
) -> Result<(), FormatError> {
    let root = doc.root_element().tag_name().name();
    if root == name {
        Ok(())
    } else {
        Err(FormatError::parse(
            format,
            format!("root element is <{root}>, expected <{name}>"),
        ))
    }
}

/// All descendant elements (including `node` itself) with the given local name.
pub(crate) fn elements<'a, 'i>(
    node: Node<'a, 'i>,
    name: &'static str,
) -> impl Iterator<Item = Node<'a, 'i>> + use<'a, 'i> {
    node.descendants()
        .filter(move |n| n.is_element() && n.tag_name().name() == name)
}

/// The first child element with the given local name.
pub(crate) fn child<'a, 'i>(node: Node<'a, 'i>, name: &str) -> Option<Node<'a, 'i>> {
    node.children()
        .find(|n| n.is_element() && n.tag_name().name() == name)
}

/// Where `node` starts, as `line L, column C`, for error messages.
pub(crate) fn position(node: Node) -> String {
    let pos = node.document().text_pos_at(node.range().start);
    format!("line {}, column {}", pos.row, pos.col)
}

/// The trimmed text of `node`, `None` when empty.
pub(crate) fn text<'a>(node: Node<'a, '_>) -> Option<&'a str> {
    node.text().map(str::trim).filter(|t| !t.is_empty())
}

/// The number in the text of `node`: `None` when the element is empty, an error when the
/// text is not a number.
pub(crate) fn number(node: Node, format: &'static str) -> Result<Option<f64>, FormatError> {
    let Some(text) = text(node) else {
        return Ok(None);
    };
    text.parse::<f64>().map(Some).map_err(|_| {
        FormatError::parse(
            format,
            format!(
                "<{}> at {}: {text:?} is not a number",
                node.tag_name().name(),
                position(node)
            ),
        )
    })
}

/// The number in the first child element called `name`, if any.
pub(crate) fn child_number(
    node: Node,
    name: &str,
    format: &'static str,
) -> Result<Option<f64>, FormatError> {
    child(node, name).map_or(Ok(None), |c| number(c, format))
}

/// Seconds since the UNIX epoch for the time in `node`: RFC 3339 (`2021-01-10T08:54:28Z`,
/// fractions and offsets allowed); a time without offset is taken as UTC.
pub(crate) fn time(node: Node, format: &'static str) -> Result<f64, FormatError> {
    let text = text(node).unwrap_or("");
    parse_time(text).ok_or_else(|| {
        FormatError::parse(
            format,
            format!(
                "<{}> at {}: invalid time {text:?}",
                node.tag_name().name(),
                position(node)
            ),
        )
    })
}

fn parse_time(text: &str) -> Option<f64> {
    let to_seconds = |secs: i64, nanos: u32| secs as f64 + f64::from(nanos) * 1e-9;
    if let Ok(t) = DateTime::parse_from_rfc3339(text) {
        return Some(to_seconds(t.timestamp(), t.timestamp_subsec_nanos()));
    }
    let naive = text.replacen(' ', "T", 1);
    let t = NaiveDateTime::parse_from_str(&naive, "%Y-%m-%dT%H:%M:%S%.f").ok()?;
    let t = t.and_utc();
    Some(to_seconds(t.timestamp(), t.timestamp_subsec_nanos()))
}

#[cfg(test)]
mod tests {
    use super::parse_time;

    #[test]
    fn times() {
        assert_eq!(parse_time("2021-01-10T08:54:28Z"), Some(1_610_268_868.0));
        assert_eq!(
            parse_time("2021-01-10T08:54:28.500Z"),
            Some(1_610_268_868.5)
        );
        assert_eq!(
            parse_time("2021-01-10T09:54:28+01:00"),
            Some(1_610_268_868.0)
        );
        assert_eq!(parse_time("2021-01-10T08:54:28"), Some(1_610_268_868.0));
        assert_eq!(parse_time("2021-01-10 08:54:28"), Some(1_610_268_868.0));
        assert_eq!(parse_time("yesterday"), None);
        assert_eq!(parse_time(""), None);
    }
}
