//! Named choices (FMI Enumerations, scene-file strings): one macro that gives an enum its
//! snake_case names, parsing and 1-based FMI index from a table of (name, description) rows.
//! It sits at the bottom of the module graph so that any module can declare a choice without
//! depending on the parameter table.

/// Declare a choice enum over a table `&[(&str, &str)]` of (name, description) rows.
#[macro_export]
macro_rules! choice_enum {
    ($(#[$m:meta])* $name:ident, $table:ident, $($variant:ident = $s:literal),+ $(,)?) => {
        $(#[$m])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize, Hash)]
        #[serde(rename_all = "snake_case")]
        pub enum $name { $($variant),+ }
        impl $name {
            /// The snake_case name used in the FMU and in scene files.
            pub fn as_str(self) -> &'static str { match self { $(Self::$variant => $s),+ } }
            /// Parse the snake_case name.
            pub fn parse(s: &str) -> Option<Self> { match s { $($s => Some(Self::$variant),)+ _ => None } }
            /// FMI enumeration index (1-based, in table order).
            pub fn index(self) -> i64 {
                $table.iter().position(|(n, _)| *n == self.as_str()).map(|i| i as i64 + 1).unwrap_or(0)
            }
            pub fn from_index(i: i64) -> Option<Self> {
                if i < 1 { return None; }
                $table.get((i - 1) as usize).and_then(|(n, _)| Self::parse(n))
            }
        }
        impl std::fmt::Display for $name {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result { f.write_str(self.as_str()) }
        }
        impl $crate::choice::Choice for $name {
            const ITEMS: &'static [(&'static str, &'static str)] = $table;
            fn name(self) -> &'static str { self.as_str() }
            fn from_name(s: &str) -> Option<Self> { Self::parse(s) }
        }
    };
}

/// What every choice offers to code that handles any of them (the parameter table stores and
/// reads an Enumeration parameter through it, whatever its enum).
pub trait Choice: Copy + 'static {
    /// The (name, description) rows, in FMI index order (item 1 first).
    const ITEMS: &'static [(&'static str, &'static str)];
    /// The snake_case name of this item.
    fn name(self) -> &'static str;
    /// The item with this snake_case name.
    fn from_name(s: &str) -> Option<Self>;
    /// FMI enumeration index (1-based, in table order); 0 for an item missing from the table.
    fn item_index(self) -> i64 {
        Self::ITEMS
            .iter()
            .position(|(n, _)| *n == self.name())
            .map_or(0, |i| i as i64 + 1)
    }
}
