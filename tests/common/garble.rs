//! Random damage to text and numbers, for the tests that feed garbage to the parsers and
//! loaders and require an error, never a panic.

use proptest::prelude::*;

/// One edit of a text: characters deleted, inserted or overwritten at a position.
#[derive(Clone, Debug)]
pub enum Edit {
    Delete(usize, usize),
    Insert(usize, String),
    Replace(usize, String),
}

pub fn edit_strategy() -> impl Strategy<Value = Edit> {
    let fragment = prop_oneof![
        "[(),:\\[\\]{}\"a-z0-9 .\\-]{1,6}",
        Just("NaN".to_owned()),
        Just("-inf".to_owned()),
        Just("1e308".to_owned()),
        Just("4294967295".to_owned()),
        Just("Compound(parts: [])".to_owned()),
    ];
    prop_oneof![
        (any::<usize>(), 1..20usize).prop_map(|(at, len)| Edit::Delete(at, len)),
        (any::<usize>(), fragment.clone()).prop_map(|(at, s)| Edit::Insert(at, s)),
        (any::<usize>(), fragment).prop_map(|(at, s)| Edit::Replace(at, s)),
    ]
}

/// Applies an edit at a character position (never inside a UTF-8 sequence).
pub fn apply(text: &str, edit: &Edit) -> String {
    let chars: Vec<char> = text.chars().collect();
    let clamp = |at: usize| at % (chars.len() + 1);
    let (start, end, insert) = match edit {
        Edit::Delete(at, len) => (clamp(*at), (clamp(*at) + len).min(chars.len()), ""),
        Edit::Insert(at, s) => (clamp(*at), clamp(*at), s.as_str()),
        Edit::Replace(at, s) => (
            clamp(*at),
            (clamp(*at) + s.len()).min(chars.len()),
            s.as_str(),
        ),
    };
    let mut edited: String = chars[..start].iter().collect();
    edited.push_str(insert);
    edited.extend(&chars[end..]);
    edited
}

pub fn number() -> impl Strategy<Value = f64> {
    prop_oneof![
        -10.0..10.0f64,
        Just(0.0),
        Just(-0.0),
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        Just(1e-320),
        Just(1e308),
        Just(-1e308),
        any::<f64>(),
    ]
}
