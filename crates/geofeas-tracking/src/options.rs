//! Described option sets of the trackers. Each set is one struct declared once with
//! [`option_set!`](crate::option_set), which gives its `Default`, its schema (the name, kind,
//! default and documentation of every option, in declaration order) and a setter by name. The
//! Python bindings read their keyword options through the setter and expose the schema, from
//! which the Python signatures take their defaults and against which the stubs, the command-line
//! flags and the docs tables are checked.

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

/// Declares an option set: a struct whose every field has a doc line and a default,
/// `#[doc = "..."] name: Type = default,`; implements `Default` and
/// [`OptionSet`](crate::options::OptionSet) from the one declaration.
#[macro_export]
macro_rules! option_set {
    (
        $(#[$meta:meta])*
        pub struct $name:ident {
            $( #[doc = $doc:literal] $field:ident : $ty:ty = $default:expr ),* $(,)?
        }
    ) => {
        $(#[$meta])*
        pub struct $name {
            $( #[doc = $doc] pub $field: $ty, )*
        }

        impl Default for $name {
            fn default() -> Self {
                Self { $( $field: $default, )* }
            }
        }

        impl $crate::options::OptionSet for $name {
            fn schema() -> Vec<$crate::options::OptionSpec> {
                use $crate::options::OptionType;
                let d = Self::default();
                vec![$(
                    $crate::options::OptionSpec {
                        name: stringify!($field),
                        kind: <$ty as OptionType>::KIND,
                        default: d.$field.to_value(),
                        doc: $doc.trim(),
                    },
                )*]
            }

            fn set(
                &mut self,
                name: &str,
                value: $crate::options::OptionValue,
            ) -> $crate::Result<()> {
                use $crate::options::OptionType;
                match name {
                    $( stringify!($field) => {
                        self.$field = <$ty as OptionType>::from_value(stringify!($field), value)?;
                    } )*
                    other => {
                        return Err($crate::Error::InvalidOption {
                            name: "options",
                            reason: format!(
                                "unexpected option '{other}' (options: {})",
                                [$(stringify!($field)),*].join(", ")
                            ),
                        })
                    }
                }
                Ok(())
            }
        }
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
}
