//! Described option sets of the trackers. Each set is one struct declared once with
//! [`option_set!`](crate::option_set), which gives its `Default`, its schema (the name, kind,
//! default and documentation of every option, in declaration order) and a setter by name. A set
//! may take named options of another set instead of declaring them again (a field holding that
//! set, the lender's schema entries, the setter delegating), so an option two sets share is
//! still declared once. The Python bindings read their keyword options through the setter and
//! expose the schema, from which the Python signatures take their defaults and against which the
//! stubs, the command-line flags and the docs tables are checked.

use geofeas::error::{Error, Result};

/// The kind of value an option takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OptionKind {
    /// `true` / `false`.
    Bool,
    /// A non-negative integer.
    Int,
    /// A finite number.
    Float,
    /// One of the listed names.
    Choice(&'static [&'static str]),
    /// A list of finite numbers, of the given length (`None`: any).
    Floats(Option<usize>),
    /// A list of non-negative integers.
    Ints,
    /// A list of names, each one of the listed ones.
    Choices(&'static [&'static str]),
    /// No value, or a list of finite numbers.
    OptionalFloats,
}

/// The value of an option.
#[derive(Debug, Clone, PartialEq)]
pub enum OptionValue {
    /// [`OptionKind::Bool`].
    Bool(bool),
    /// [`OptionKind::Int`].
    Int(u64),
    /// [`OptionKind::Float`].
    Float(f64),
    /// [`OptionKind::Choice`].
    Text(String),
    /// [`OptionKind::Floats`], or [`OptionKind::OptionalFloats`] when given.
    Floats(Vec<f64>),
    /// [`OptionKind::Ints`].
    Ints(Vec<u64>),
    /// [`OptionKind::Choices`].
    Texts(Vec<String>),
    /// [`OptionKind::OptionalFloats`] when not given.
    None,
}

/// One option of a set: what the schema says about it.
#[derive(Debug, Clone, PartialEq)]
pub struct OptionSpec {
    /// The keyword.
    pub name: &'static str,
    /// The kind of value.
    pub kind: OptionKind,
    /// The default.
    pub default: OptionValue,
    /// One line of documentation.
    pub doc: &'static str,
}

/// A type an option may have.
pub trait OptionType: Sized {
    /// The kind of value.
    const KIND: OptionKind;
    /// The value.
    fn to_value(&self) -> OptionValue;
    /// The value read back; errors name the option.
    fn from_value(name: &'static str, value: OptionValue) -> Result<Self>;
}

/// A described option set, declared with [`option_set!`](crate::option_set).
pub trait OptionSet: Default {
    /// Every option, in declaration order, with its default.
    fn schema() -> Vec<OptionSpec>;
    /// Sets the option `name`; errors name it (or say that no such option exists).
    fn set(&mut self, name: &str, value: OptionValue) -> Result<()>;
}

fn mismatch(name: &'static str, kind: OptionKind, value: &OptionValue) -> Error {
    Error::InvalidOption {
        name,
        reason: format!("expected {kind:?}, got {value:?}"),
    }
}

fn finite(name: &'static str, v: f64) -> Result<f64> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(Error::InvalidOption {
            name,
            reason: format!("must be finite, got {v}"),
        })
    }
}

impl OptionType for bool {
    const KIND: OptionKind = OptionKind::Bool;
    fn to_value(&self) -> OptionValue {
        OptionValue::Bool(*self)
    }
    fn from_value(name: &'static str, value: OptionValue) -> Result<Self> {
        match value {
            OptionValue::Bool(b) => Ok(b),
            v => Err(mismatch(name, Self::KIND, &v)),
        }
    }
}

macro_rules! int_option {
    ($($t:ty),*) => {$(
        impl OptionType for $t {
            const KIND: OptionKind = OptionKind::Int;
            fn to_value(&self) -> OptionValue {
                OptionValue::Int(*self as u64)
            }
            fn from_value(name: &'static str, value: OptionValue) -> Result<Self> {
                match value {
                    OptionValue::Int(i) => <$t>::try_from(i).map_err(|_| Error::InvalidOption {
                        name,
                        reason: format!("{i} is out of range"),
                    }),
                    v => Err(mismatch(name, Self::KIND, &v)),
                }
            }
        }
    )*};
}
int_option!(usize, u64, u32);

impl OptionType for f64 {
    const KIND: OptionKind = OptionKind::Float;
    fn to_value(&self) -> OptionValue {
        OptionValue::Float(*self)
    }
    fn from_value(name: &'static str, value: OptionValue) -> Result<Self> {
        match value {
            OptionValue::Float(x) => finite(name, x),
            OptionValue::Int(i) => Ok(i as f64),
            v => Err(mismatch(name, Self::KIND, &v)),
        }
    }
}

impl<const N: usize> OptionType for [f64; N] {
    const KIND: OptionKind = OptionKind::Floats(Some(N));
    fn to_value(&self) -> OptionValue {
        OptionValue::Floats(self.to_vec())
    }
    fn from_value(name: &'static str, value: OptionValue) -> Result<Self> {
        match value {
            OptionValue::Floats(v) => {
                let got = v.len();
                let v = v
                    .into_iter()
                    .map(|x| finite(name, x))
                    .collect::<Result<Vec<_>>>()?;
                <[f64; N]>::try_from(v).map_err(|_| Error::InvalidOption {
                    name,
                    reason: format!("expected {N} numbers, got {got}"),
                })
            }
            v => Err(mismatch(name, Self::KIND, &v)),
        }
    }
}

impl OptionType for Option<Vec<f64>> {
    const KIND: OptionKind = OptionKind::OptionalFloats;
    fn to_value(&self) -> OptionValue {
        match self {
            Some(v) => OptionValue::Floats(v.clone()),
            None => OptionValue::None,
        }
    }
    fn from_value(name: &'static str, value: OptionValue) -> Result<Self> {
        match value {
            OptionValue::None => Ok(None),
            OptionValue::Floats(v) => Ok(Some(
                v.into_iter()
                    .map(|x| finite(name, x))
                    .collect::<Result<_>>()?,
            )),
            v => Err(mismatch(name, Self::KIND, &v)),
        }
    }
}

impl OptionType for Vec<usize> {
    const KIND: OptionKind = OptionKind::Ints;
    fn to_value(&self) -> OptionValue {
        OptionValue::Ints(self.iter().map(|&i| i as u64).collect())
    }
    fn from_value(name: &'static str, value: OptionValue) -> Result<Self> {
        match value {
            OptionValue::Ints(v) => v
                .into_iter()
                .map(|i| usize::from_value(name, OptionValue::Int(i)))
                .collect(),
            v => Err(mismatch(name, Self::KIND, &v)),
        }
    }
}

/// A type named by one of a fixed list of names.
pub trait Named: Sized + Copy + 'static {
    /// Every name, in order.
    const NAMES: &'static [&'static str];
    /// The name of the value.
    fn name(&self) -> &'static str;
    /// The value of a name; errors name the option.
    fn from_name(name: &str) -> Result<Self>;
}

/// A list of values named by one of a fixed list of names.
#[derive(Debug, Clone, PartialEq)]
pub struct NamedList<T>(pub Vec<T>);

impl<T: Named> OptionType for T {
    const KIND: OptionKind = OptionKind::Choice(T::NAMES);
    fn to_value(&self) -> OptionValue {
        OptionValue::Text(self.name().to_string())
    }
    fn from_value(name: &'static str, value: OptionValue) -> Result<Self> {
        match value {
            OptionValue::Text(s) => T::from_name(&s),
            v => Err(mismatch(name, Self::KIND, &v)),
        }
    }
}

impl<T: Named> OptionType for NamedList<T> {
    const KIND: OptionKind = OptionKind::Choices(T::NAMES);
    fn to_value(&self) -> OptionValue {
        OptionValue::Texts(self.0.iter().map(|t| t.name().to_string()).collect())
    }
    fn from_value(name: &'static str, value: OptionValue) -> Result<Self> {
        match value {
            OptionValue::Texts(v) => Ok(Self(
                v.iter().map(|s| T::from_name(s)).collect::<Result<_>>()?,
            )),
            v => Err(mismatch(name, Self::KIND, &v)),
        }
    }
}

/// The schema entries of the option set `L` named `names`, in that order: what a set declared
/// with [`option_set!`](crate::option_set) shows of the options it takes from `L`.
///
/// # Panics
/// If `L` has no option of one of the names (a mistake in the declaration of `borrower`).
#[doc(hidden)]
pub fn borrowed<L: OptionSet>(borrower: &str, names: &[&str]) -> Vec<OptionSpec> {
    let lender = L::schema();
    names
        .iter()
        .map(|n| {
            lender
                .iter()
                .find(|s| s.name == *n)
                .cloned()
                .unwrap_or_else(|| {
                    panic!(
                        "{borrower}: '{n}' is not an option of {}",
                        std::any::type_name::<L>()
                    )
                })
        })
        .collect()
}

/// `schema`, checked to name each option once.
///
/// # Panics
/// If two options of `set` have the same name (a mistake in its declaration).
#[doc(hidden)]
pub fn distinct(set: &str, schema: Vec<OptionSpec>) -> Vec<OptionSpec> {
    for (i, s) in schema.iter().enumerate() {
        assert!(
            schema[..i].iter().all(|t| t.name != s.name),
            "{set}: two options named '{}'",
            s.name
        );
    }
    schema
}

/// Declares an option set: a struct whose every item has a doc line, in one of two forms.
///
/// - An option of the set's own, `#[doc = "..."] name: Type = default,` (a field `name` of type
///   `Type`, starting at `default`).
/// - Options taken from another option set, `#[doc = "..."] field: Set { a, b, c },`: a field
///   `field` of type `Set` (starting at `Set::default()`) whose options `a`, `b` and `c` the set
///   takes as its own, declared once in `Set`: their schema entries are `Set`'s (kind, default,
///   doc), and setting one sets it in `field`. `Set`'s other options are not the set's.
///
/// Implements `Default` and [`OptionSet`](crate::options::OptionSet) from the one declaration.
/// The schema follows the declaration: the set's own options and the taken ones in the order
/// the items and the braced lists give them (so a taken option sits where the set lists it, not
/// where `Set` declares it). A name declared twice, or taken but not an option of `Set`, makes
/// `schema()` panic.
#[macro_export]
macro_rules! option_set {
    (
        $(#[$meta:meta])*
        pub struct $name:ident {
            $($body:tt)*
        }
    ) => {
        $crate::option_set!(@parse [$(#[$meta])*] $name [] [] [] $($body)*);
    };

    // Options taken from another set: `#[doc = "..."] field: Set { a, b, c },`.
    (@parse $meta:tt $name:ident [$($own:tt)*] [$($taken:tt)*] [$($item:tt)*]
        #[doc = $doc:literal] $field:ident : $set:ident { $($n:ident),* $(,)? }
        $(, $($rest:tt)*)?
    ) => {
        $crate::option_set!(@parse $meta $name
            [$($own)*]
            [$($taken)* [#[doc = $doc] $field : $set { $($n),* }]]
            [$($item)* (taken $field $set [$($n)*])]
            $($($rest)*)?
        );
    };

    // An option of the set's own: `#[doc = "..."] name: Type = default,`.
    (@parse $meta:tt $name:ident [$($own:tt)*] [$($taken:tt)*] [$($item:tt)*]
        #[doc = $doc:literal] $field:ident : $ty:ty = $default:expr
        $(, $($rest:tt)*)?
    ) => {
        $crate::option_set!(@parse $meta $name
            [$($own)* [#[doc = $doc] $field : $ty = $default]]
            [$($taken)*]
            [$($item)* (own $field $doc $ty)]
            $($($rest)*)?
        );
    };

    (@parse [$($meta:tt)*] $name:ident
        [$([#[doc = $doc:literal] $field:ident : $ty:ty = $default:expr])*]
        [$([#[doc = $tdoc:literal] $tfield:ident : $set:ident { $($n:ident),* }])*]
        [$($item:tt)*]
    ) => {
        $($meta)*
        pub struct $name {
            $( #[doc = $doc] pub $field: $ty, )*
            $( #[doc = $tdoc] pub $tfield: $set, )*
        }

        impl Default for $name {
            fn default() -> Self {
                Self {
                    $( $field: $default, )*
                    $( $tfield: <$set as Default>::default(), )*
                }
            }
        }

        impl $crate::options::OptionSet for $name {
            fn schema() -> Vec<$crate::options::OptionSpec> {
                #[allow(unused_variables)]
                let d = Self::default();
                // the items in declaration order, each one option or those taken from a set
                let items: Vec<Vec<$crate::options::OptionSpec>> =
                    vec![$( $crate::option_set!(@spec $name d $item) ),*];
                $crate::options::distinct(stringify!($name), items.concat())
            }

            fn set(
                &mut self,
                name: &str,
                value: $crate::options::OptionValue,
            ) -> $crate::Result<()> {
                $( if name == stringify!($field) {
                    self.$field = <$ty as $crate::options::OptionType>::from_value(
                        stringify!($field),
                        value,
                    )?;
                    return Ok(());
                } )*
                $( if [$(stringify!($n)),*].contains(&name) {
                    return <$set as $crate::options::OptionSet>::set(&mut self.$tfield, name, value);
                } )*
                let names: Vec<_> = <Self as $crate::options::OptionSet>::schema()
                    .iter()
                    .map(|o| o.name)
                    .collect();
                Err($crate::Error::InvalidOption {
                    name: "options",
                    reason: format!(
                        "unexpected option '{name}' (options: {})",
                        names.join(", ")
                    ),
                })
            }
        }
    };

    (@spec $name:ident $d:ident (own $field:ident $doc:literal $ty:ty)) => {
        vec![$crate::options::OptionSpec {
            name: stringify!($field),
            kind: <$ty as $crate::options::OptionType>::KIND,
            default: $crate::options::OptionType::to_value(&$d.$field),
            doc: $doc.trim(),
        }]
    };

    (@spec $name:ident $d:ident (taken $field:ident $set:ident [$($n:ident)*])) => {
        $crate::options::borrowed::<$set>(
            concat!(stringify!($name), ".", stringify!($field)),
            &[$(stringify!($n)),*],
        )
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    crate::option_set! {
        /// A set for the tests.
        #[derive(Debug, Clone, PartialEq)]
        pub struct Example {
            /// A count.
            count: usize = 4,
            /// A scale.
            scale: f64 = 0.5,
            /// Three factors.
            factors: [f64; 3] = [0.8, 1.5, 1.5],
            /// Optional grid.
            grid: Option<Vec<f64>> = None,
        }
    }

    crate::option_set! {
        /// A set taking two options of [`Example`], in another order than `Example`'s.
        #[derive(Debug, Clone, PartialEq)]
        pub struct Borrower {
            /// Runs.
            runs: usize = 2,
            /// The options of the example the set takes.
            example: Example { scale, count },
            /// A level.
            level: f64 = 0.9,
        }
    }

    crate::option_set! {
        /// A set taking an option its lender does not have.
        #[derive(Debug)]
        pub struct Mistaken {
            /// The options of the example the set takes.
            example: Example { scale, speed },
        }
    }

    crate::option_set! {
        /// A set declaring one name twice.
        #[derive(Debug)]
        pub struct Twice {
            /// Another scale.
            scale: f64 = 1.0,
            /// The options of the example the set takes.
            example: Example { scale },
        }
    }

    #[test]
    fn schema_lists_every_field_with_its_default() {
        let s = Example::schema();
        let names: Vec<_> = s.iter().map(|o| o.name).collect();
        assert_eq!(names, ["count", "scale", "factors", "grid"]);
        assert_eq!(s[0].default, OptionValue::Int(4));
        assert_eq!(s[0].doc, "A count.");
        assert_eq!(s[2].kind, OptionKind::Floats(Some(3)));
        assert_eq!(s[2].default, OptionValue::Floats(vec![0.8, 1.5, 1.5]));
        assert_eq!(s[3].default, OptionValue::None);
    }

    #[test]
    fn set_reads_back_and_refuses_with_the_name() {
        let mut e = Example::default();
        e.set("count", OptionValue::Int(9)).unwrap();
        e.set("scale", OptionValue::Int(2)).unwrap();
        e.set("grid", OptionValue::Floats(vec![1.0])).unwrap();
        assert_eq!(
            e,
            Example {
                count: 9,
                scale: 2.0,
                grid: Some(vec![1.0]),
                ..Example::default()
            }
        );
        let err = e.set("bogus", OptionValue::Int(1)).unwrap_err();
        assert!(err.to_string().contains("bogus"), "{err}");
        let err = e
            .set("scale", OptionValue::Float(f64::NAN))
            .unwrap_err()
            .to_string();
        assert!(err.contains("scale"), "{err}");
        let err = e
            .set("factors", OptionValue::Floats(vec![1.0]))
            .unwrap_err()
            .to_string();
        assert!(err.contains("factors") && err.contains('3'), "{err}");
        let err = e
            .set("count", OptionValue::Text("x".into()))
            .unwrap_err()
            .to_string();
        assert!(err.contains("count"), "{err}");
    }

    #[test]
    fn taken_options_are_the_lenders() {
        let lender = Example::schema();
        let s = Borrower::schema();
        let names: Vec<_> = s.iter().map(|o| o.name).collect();
        assert_eq!(names, ["runs", "scale", "count", "level"]);
        for taken in &s[1..3] {
            let own = lender.iter().find(|o| o.name == taken.name).unwrap();
            assert_eq!(
                (taken.name, taken.kind, &taken.default, taken.doc),
                (own.name, own.kind, &own.default, own.doc)
            );
        }
        assert_eq!(Borrower::default().example, Example::default());
        assert_eq!(s[0].doc, "Runs.");
        assert_eq!(s[3].default, OptionValue::Float(0.9));
    }

    #[test]
    fn setting_a_taken_option_sets_the_lenders_field() {
        let mut b = Borrower::default();
        b.set("scale", OptionValue::Int(3)).unwrap();
        b.set("count", OptionValue::Int(7)).unwrap();
        b.set("runs", OptionValue::Int(5)).unwrap();
        assert_eq!(
            b,
            Borrower {
                runs: 5,
                example: Example {
                    scale: 3.0,
                    count: 7,
                    ..Example::default()
                },
                ..Borrower::default()
            }
        );
        // the lender checks the value and names the option
        let err = b
            .set("scale", OptionValue::Float(f64::INFINITY))
            .unwrap_err()
            .to_string();
        assert!(err.contains("scale"), "{err}");
        assert_eq!(b.example.scale, 3.0);
        // an option of the lender the set does not take is not the set's
        for name in ["factors", "bogus"] {
            let err = b.set(name, OptionValue::Int(1)).unwrap_err().to_string();
            assert!(
                err.contains(&format!("'{name}'")) && err.contains("runs, scale, count, level"),
                "{err}"
            );
        }
        assert_eq!(
            b.example,
            Example {
                scale: 3.0,
                count: 7,
                ..Example::default()
            }
        );
    }

    #[test]
    #[should_panic(expected = "Mistaken.example: 'speed' is not an option of")]
    fn taking_an_option_the_lender_lacks_is_refused() {
        Mistaken::schema();
    }

    #[test]
    #[should_panic(expected = "Twice: two options named 'scale'")]
    fn a_name_declared_twice_is_refused() {
        Twice::schema();
    }
}
