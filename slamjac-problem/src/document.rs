//! A JSON document read into one arena: every value a node of one vector
//! (each array's items and each object's members side by side), every
//! string and key in one text. Reading a problem file of some ten megabytes
//! (half a million values) then fills a few large buffers rather than
//! allocating a million small ones, and its values are read through
//! handles ([`Json`]) that are copied, not borrowed from a tree of boxes.
//!
//! Objects keep their members in the order written; one with more than
//! `INDEXED` (16) members (a problem file's `variables`, its `truth`) also
//! keeps them sorted by key, so that a member is found by bisection.
//! Numbers are finite `f64`: the readers ([`crate::strict_json`]) refuse
//! any other.

use serde_json::{Map, Number, Value};

/// The most members an object is searched through one by one.
const INDEXED: usize = 16;

/// A JSON document (see the module documentation).
#[derive(Debug, Clone, Default)]
pub struct Document {
    nodes: Vec<Node>,
    /// Each node's key, where it is an object's member.
    keys: Vec<Span>,
    text: String,
    /// The members of each object of more than [`INDEXED`], by key: their
    /// indices among the object's members, end to end.
    sorted: Vec<u32>,
}

/// A string of the text.
#[derive(Debug, Clone, Copy, Default)]
struct Span {
    start: u32,
    len: u32,
}

#[derive(Debug, Clone, Copy)]
enum Node {
    Null,
    Bool(bool),
    Number(f64),
    String(Span),
    /// Items `first..first + len` of the nodes.
    Array {
        first: u32,
        len: u32,
    },
    /// Members `first..first + len` of the nodes; where there are more
    /// than [`INDEXED`], their order by key from `sorted` on.
    Object {
        first: u32,
        len: u32,
        sorted: u32,
    },
}

/// A value of a [`Document`].
#[derive(Debug, Clone, Copy)]
pub struct Json<'a> {
    document: &'a Document,
    node: u32,
}

/// The members of an object of a [`Document`], in the order written.
#[derive(Debug, Clone, Copy)]
pub struct Members<'a> {
    document: &'a Document,
    first: u32,
    len: u32,
    sorted: u32,
}

/// The items of an array of a [`Document`].
#[derive(Debug, Clone, Copy)]
pub struct Items<'a> {
    document: &'a Document,
    first: u32,
    len: u32,
}

impl Document {
    /// The document's value.
    pub fn root(&self) -> Json<'_> {
        Json {
            document: self,
            node: u32::try_from(self.nodes.len() - 1).expect("fewer than 2³² values"),
        }
    }

    /// `value` as a document (its numbers as `f64`).
    pub fn from_value(value: &Value) -> Document {
        let mut builder = Builder::default();
        builder.value(value);
        builder.finish()
    }

    fn text(&self, span: Span) -> &str {
        &self.text[span.start as usize..(span.start + span.len) as usize]
    }

    /// The key of member node `node`.
    fn key(&self, node: u32) -> &str {
        self.text(self.keys[node as usize])
    }
}

impl<'a> Json<'a> {
    fn node(self) -> Node {
        self.document.nodes[self.node as usize]
    }

    /// Its members, if it is an object.
    pub fn as_object(self) -> Option<Members<'a>> {
        match self.node() {
            Node::Object { first, len, sorted } => Some(Members {
                document: self.document,
                first,
                len,
                sorted,
            }),
            _ => None,
        }
    }

    /// Its items, if it is an array.
    pub fn as_array(self) -> Option<Items<'a>> {
        match self.node() {
            Node::Array { first, len } => Some(Items {
                document: self.document,
                first,
                len,
            }),
            _ => None,
        }
    }

    /// The string, if it is one.
    pub fn as_str(self) -> Option<&'a str> {
        match self.node() {
            Node::String(span) => Some(self.document.text(span)),
            _ => None,
        }
    }

    /// The number, if it is one.
    pub fn as_f64(self) -> Option<f64> {
        match self.node() {
            Node::Number(x) => Some(x),
            _ => None,
        }
    }

    /// The boolean, if it is one.
    pub fn as_bool(self) -> Option<bool> {
        match self.node() {
            Node::Bool(b) => Some(b),
            _ => None,
        }
    }

    /// Whether it is an object.
    pub fn is_object(self) -> bool {
        self.as_object().is_some()
    }

    /// Whether it is an array.
    pub fn is_array(self) -> bool {
        self.as_array().is_some()
    }

    /// Member `key`, if it is an object that has one.
    pub fn get(self, key: &str) -> Option<Json<'a>> {
        self.as_object()?.get(key)
    }

    /// What kind of value it is, for "expected X, found Y": `null`, `a
    /// boolean`, `a number`, `a string`, `an array` or `an object`.
    pub fn kind(self) -> &'static str {
        match self.node() {
            Node::Null => "null",
            Node::Bool(_) => "a boolean",
            Node::Number(_) => "a number",
            Node::String(_) => "a string",
            Node::Array { .. } => "an array",
            Node::Object { .. } => "an object",
        }
    }

    /// The value as `serde_json` holds it (to write it out).
    pub fn to_value(self) -> Value {
        match self.node() {
            Node::Null => Value::Null,
            Node::Bool(b) => Value::Bool(b),
            Node::Number(x) => Number::from_f64(x).map_or(Value::Null, Value::Number),
            Node::String(span) => Value::String(self.document.text(span).to_owned()),
            Node::Array { .. } => Value::Array(
                self.as_array()
                    .into_iter()
                    .flat_map(|items| items.iter())
                    .map(Json::to_value)
                    .collect(),
            ),
            Node::Object { .. } => Value::Object(
                self.as_object()
                    .into_iter()
                    .flat_map(|members| members.iter())
                    .map(|(key, value)| (key.to_owned(), value.to_value()))
                    .collect::<Map<String, Value>>(),
            ),
        }
    }
}

impl<'a> Members<'a> {
    /// How many members.
    pub fn len(self) -> usize {
        self.len as usize
    }

    /// Whether there are none.
    pub fn is_empty(self) -> bool {
        self.len == 0
    }

    fn member(self, k: u32) -> (&'a str, Json<'a>) {
        let node = self.first + k;
        let json = Json {
            document: self.document,
            node,
        };
        (self.document.key(node), json)
    }

    /// The members, keys with values, in the order written.
    pub fn iter(self) -> impl Iterator<Item = (&'a str, Json<'a>)> {
        (0..self.len).map(move |k| self.member(k))
    }

    /// The keys, in the order written.
    pub fn keys(self) -> impl Iterator<Item = &'a str> {
        self.iter().map(|(key, _)| key)
    }

    /// Member `key`'s value.
    pub fn get(self, key: &str) -> Option<Json<'a>> {
        if self.len() <= INDEXED {
            return self.iter().find(|(k, _)| *k == key).map(|(_, v)| v);
        }
        let start = self.sorted as usize;
        let order = &self.document.sorted[start..start + self.len()];
        let k = order
            .binary_search_by(|&m| self.member(m).0.cmp(key))
            .ok()?;
        Some(self.member(order[k]).1)
    }

    /// Whether there is a member `key`.
    pub fn contains_key(self, key: &str) -> bool {
        self.get(key).is_some()
    }
}

impl<'a> Items<'a> {
    /// How many items.
    pub fn len(self) -> usize {
        self.len as usize
    }

    /// Whether there are none.
    pub fn is_empty(self) -> bool {
        self.len == 0
    }

    /// The items, in order.
    pub fn iter(self) -> impl Iterator<Item = Json<'a>> {
        let document = self.document;
        (self.first..self.first + self.len).map(move |node| Json { document, node })
    }
}

/// A container being read: where its values start among the open ones,
/// and its own key.
#[derive(Debug)]
pub(crate) struct Open {
    start: usize,
    key: Span,
}

/// Builds a [`Document`] value by value, depth first: each value is pushed
/// when read, and a container's values move to the document, side by
/// side, when it closes.
#[derive(Debug, Default)]
pub(crate) struct Builder {
    document: Document,
    /// The values read and not yet in a closed container, each with its
    /// key (empty for an array's item).
    open: Vec<(Node, Span)>,
    /// The key of the member being read.
    key: Span,
}

impl Builder {
    fn push(&mut self, node: Node) {
        let key = std::mem::take(&mut self.key);
        self.open.push((node, key));
    }

    fn span(&mut self, text: &str) -> Span {
        let start = u32::try_from(self.document.text.len()).expect("less than 4 GiB of text");
        self.document.text.push_str(text);
        Span {
            start,
            len: u32::try_from(text.len()).expect("less than 4 GiB of text"),
        }
    }

    pub(crate) fn null(&mut self) {
        self.push(Node::Null);
    }

    pub(crate) fn bool(&mut self, b: bool) {
        self.push(Node::Bool(b));
    }

    /// A number (finite: the readers refuse any other).
    pub(crate) fn number(&mut self, x: f64) {
        self.push(Node::Number(x));
    }

    pub(crate) fn string(&mut self, text: &str) {
        let span = self.span(text);
        self.push(Node::String(span));
    }

    /// The key of the next value (an object's member).
    pub(crate) fn key(&mut self, key: &str) {
        self.key = self.span(key);
    }

    /// Opens a container, for [`Builder::array`] or [`Builder::object`]
    /// to close.
    pub(crate) fn open(&mut self) -> Open {
        Open {
            start: self.open.len(),
            key: std::mem::take(&mut self.key),
        }
    }

    /// The values read since `start` moved to the document, side by side.
    fn close(&mut self, start: usize) -> (u32, u32) {
        let first = u32::try_from(self.document.nodes.len()).expect("fewer than 2³² values");
        let len = u32::try_from(self.open.len() - start).expect("fewer than 2³² values");
        for (node, key) in self.open.drain(start..) {
            self.document.nodes.push(node);
            self.document.keys.push(key);
        }
        (first, len)
    }

    /// Closes the array `opened`.
    pub(crate) fn array(&mut self, opened: Open) {
        let (first, len) = self.close(opened.start);
        self.key = opened.key;
        self.push(Node::Array { first, len });
    }

    /// Closes the object `opened`; `false` (nothing closed) if two of its
    /// members have the same key.
    pub(crate) fn object(&mut self, opened: Open) -> bool {
        let members = &self.open[opened.start..];
        let text =
            |span: Span| &self.document.text[span.start as usize..(span.start + span.len) as usize];
        let sorted = if members.len() <= INDEXED {
            let duplicate = members
                .iter()
                .enumerate()
                .any(|(i, (_, a))| members[i + 1..].iter().any(|(_, b)| text(*a) == text(*b)));
            if duplicate {
                return false;
            }
            0
        } else {
            let mut order: Vec<u32> = (0..members.len() as u32).collect();
            order.sort_unstable_by(|&a, &b| {
                text(members[a as usize].1).cmp(text(members[b as usize].1))
            });
            if order
                .windows(2)
                .any(|w| text(members[w[0] as usize].1) == text(members[w[1] as usize].1))
            {
                return false;
            }
            let sorted = u32::try_from(self.document.sorted.len()).expect("fewer than 2³² values");
            self.document.sorted.extend(order);
            sorted
        };
        let (first, len) = self.close(opened.start);
        self.key = opened.key;
        self.push(Node::Object { first, len, sorted });
        true
    }

    /// The document whose value was read (the one value pushed and not
    /// in a container).
    pub(crate) fn finish(mut self) -> Document {
        self.close(0);
        self.document
    }

    /// Pushes `value` whole.
    fn value(&mut self, value: &Value) {
        match value {
            Value::Null => self.null(),
            Value::Bool(b) => self.bool(*b),
            Value::Number(n) => self.number(n.as_f64().unwrap_or(f64::NAN)),
            Value::String(s) => self.string(s),
            Value::Array(items) => {
                let opened = self.open();
                for item in items {
                    self.value(item);
                }
                self.array(opened);
            }
            Value::Object(map) => {
                let opened = self.open();
                for (key, item) in map {
                    self.key(key);
                    self.value(item);
                }
                // The keys of a map are distinct.
                self.object(opened);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    /// A value read into a document reads back as itself, whatever the
    /// size of its objects; members are found by key in either kind of
    /// object, and kinds are named.
    #[test]
    fn values_read_back_as_they_were_written() {
        let large: Map<String, Value> = (0..40)
            .rev()
            .map(|k| (format!("v{k}"), json!([k as f64, {"type": "Vector3"}])))
            .collect();
        let value = json!({
            "a": [1.5, -2.0, true, false, null, "x\u{e9}", [], {}],
            "b": {"c": {"d": "e"}},
            "": 0.0,
            "large": large,
        });
        let document = Document::from_value(&value);
        let root = document.root();
        assert_eq!(root.to_value(), value);
        let large = root.get("large").unwrap().as_object().unwrap();
        assert_eq!(large.len(), 40);
        assert_eq!(large.keys().next(), Some("v39"), "the order written");
        for k in 0..40 {
            let member = large.get(&format!("v{k}")).unwrap();
            assert_eq!(
                member.as_array().unwrap().iter().next().unwrap().as_f64(),
                Some(k as f64)
            );
        }
        assert!(large.get("v40").is_none() && large.get("").is_none());
        assert_eq!(root.get("").and_then(Json::as_f64), Some(0.0));
        assert_eq!(
            root.get("b")
                .and_then(|b| b.get("c"))
                .and_then(|c| c.get("d"))
                .and_then(Json::as_str),
            Some("e")
        );
        let kinds: Vec<&str> = root
            .get("a")
            .unwrap()
            .as_array()
            .unwrap()
            .iter()
            .map(Json::kind)
            .collect();
        assert_eq!(
            kinds,
            [
                "a number",
                "a number",
                "a boolean",
                "a boolean",
                "null",
                "a string",
                "an array",
                "an object"
            ]
        );
        assert_eq!(Document::from_value(&json!(7)).root().as_f64(), Some(7.0));
    }

    /// An object with a key twice is not closed, small or large.
    #[test]
    fn duplicate_keys_are_found() {
        for n in [2, INDEXED + 5] {
            let mut builder = Builder::default();
            let opened = builder.open();
            for k in 0..n {
                builder.key(&format!("k{}", k % (n - 1)));
                builder.null();
            }
            assert!(!builder.object(opened), "{n} members");
        }
    }
}
