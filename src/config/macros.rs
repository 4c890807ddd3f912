//! [`params!`](crate::params): one declaration per parameter.

/// Declare a group of parameters: each field is written once, with its row of the parameter
/// table, and the macro generates the struct (the description is the field's documentation),
/// its rows (`ROWS`: FMU variable, scene-file key, value reference, unit, range), its
/// `Default` (the rows' defaults) and its [`ParamGroup`](crate::config::ParamGroup)
/// implementation (read and store by name). Range checks are the row's
/// ([`Kind::check`](crate::config::Kind::check)), done once for every group by the
/// configuration that holds it.
///
/// ```ignore
/// viscosph::params! {
///     /// The drop of Fang 2006 section 4.
///     pub struct DropParams {
///         drop_diameter: f64 = real_pos(0.02, 10.0), vr 6, unit "m";
///             "Diameter of the initial (circular) drop",
///         initial_drop_height: f64 = real_pos(0.04, 100.0), vr 7, unit "m", alias "drop_height";
///             "Height of the drop centre above the impact point at t = 0",
///     }
/// }
/// ```
///
/// After the unit, `alias "old_name"` gives an older scene-file key and `input` makes the row an
/// FMU input (see [`ParamSpec`](crate::config::ParamSpec)). The field's name is the FMU name.
#[macro_export]
macro_rules! params {
    (@alias) => { None };
    (@alias alias $alias:literal $($rest:tt)*) => { Some($alias) };
    (@alias $flag:ident $($rest:tt)*) => { $crate::params!(@alias $($rest)*) };
    (@input) => { false };
    (@input input $($rest:tt)*) => { true };
    (@input $flag:ident $($rest:tt)*) => { $crate::params!(@input $($rest)*) };
    (@input $other:literal $($rest:tt)*) => { $crate::params!(@input $($rest)*) };
    (
        $(#[$meta:meta])*
        $vis:vis struct $name:ident {
            $(
                $field:ident : $ty:ty = $kind:expr, vr $vr:literal, unit $unit:literal
                    $(, $flag:ident $($flag_arg:literal)?)* ;
                    $desc:literal
            ),* $(,)?
        }
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
        #[allow(non_snake_case)]
        $vis struct $name {
            $( #[doc = $desc] pub $field: $ty, )*
        }

        impl $name {
            /// The rows of this group, in declaration order.
            pub const ROWS: &'static [$crate::config::ParamSpec] = &[
                $(
                    $crate::config::ParamSpec {
                        name: stringify!($field),
                        value_reference: $vr,
                        kind: $kind,
                        unit: $unit,
                        description: $desc,
                        alias: $crate::params!(@alias $($flag $($flag_arg)?)*),
                        input: $crate::params!(@input $($flag $($flag_arg)?)*),
                    },
                )*
            ];
        }

        impl Default for $name {
            /// The rows' defaults.
            fn default() -> Self {
                Self {
                    $(
                        $field: <$ty as $crate::config::ParamValue>::from_checked(
                            ($kind).default_value(),
                        ),
                    )*
                }
            }
        }

        impl $crate::config::ParamGroup for $name {
            fn collect_rows(out: &mut Vec<&'static $crate::config::ParamSpec>) {
                out.extend(Self::ROWS.iter());
            }
            fn value(&self, name: &str) -> Option<$crate::config::Value> {
                $(
                    if name == stringify!($field) {
                        return Some($crate::config::ParamValue::to_value(self.$field));
                    }
                )*
                let _ = name;
                None
            }
            fn store(&mut self, name: &str, v: $crate::config::Checked) -> bool {
                $(
                    if name == stringify!($field) {
                        self.$field = $crate::config::ParamValue::from_checked(v);
                        return true;
                    }
                )*
                let _ = (name, v);
                false
            }
        }
    };
}
