//! The `schema!` macro that generates the parameter table from its rows
//! ([`super::table`]): [`ParamId`](super::ParamId), [`PARAMS`](super::PARAMS),
//! [`PARAM_COUNT`](super::PARAM_COUNT) and each choice row's `ChoiceRow` link. It expands in
//! `table.rs`, where its names resolve.

/// Generate the table from its rows (see [`super::table`]).
macro_rules! schema {
    ($(
        $(#[$id_doc:meta])*
        $Id:ident {
            key: $key:literal,
            name: $name:literal,
            unit: $unit:literal,
            values: $values:ident $(::<$E:ty>)? ( $($arg:expr),* ),
            default: $default:expr,
            place: $place:expr,
            group: $group:expr,
            doc: $doc:literal,
        },
    )+) => {
        /// Identifies a parameter; the discriminant indexes [`PARAMS`] and
        /// [`Params`](super::Params).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        #[repr(usize)]
        pub enum ParamId {
            $( $(#[$id_doc])* $Id, )+
        }

        /// Number of parameters.
        pub const PARAM_COUNT: usize = [$($key),+].len();

        /// The parameter table, indexed by [`ParamId`].
        pub const PARAMS: [ParamSpec; PARAM_COUNT] = [$({
            let values = $values $(::<$E>)? ($($arg),*);
            ParamSpec {
                id: ParamId::$Id,
                key: $key,
                name: $name,
                unit: $unit,
                min: values.min,
                max: values.max,
                default: $default,
                kind: values.kind,
                place: $place,
                group: $group,
                doc: $doc,
            }
        }),+];

        $($(
            impl ChoiceRow for $E {
                const ID: ParamId = ParamId::$Id;
            }
        )?)+
    };
}
