//! The violin and the bow as rigid objects: the points a performer track carries for them.

/// A point on the violin or the bow. Strings are numbered 0 = G … 3 = E.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum InstrumentPart {
    /// End of the scroll.
    ViolinScroll,
    /// The nut (centre of its top edge).
    ViolinNut,
    /// Centre of the body (under the bridge).
    ViolinBody,
    /// The bridge (centre of its top).
    ViolinBridge,
    /// The end button (tail end, under the chin).
    ViolinEndButton,
    /// A string's end at the nut.
    StringAtNut(u8),
    /// A string's end at the bridge.
    StringAtBridge(u8),
    /// The bow's frog end (the stick).
    BowFrog,
    /// The bow's tip.
    BowTip,
    /// Where the hair starts at the frog.
    BowHairFrog,
    /// Where the hair ends at the tip.
    BowHairTip,
}

/// Number of instrument parts.
pub const INSTRUMENT_PART_COUNT: usize = 17;

impl InstrumentPart {
    /// All parts in file order.
    pub const ALL: [InstrumentPart; INSTRUMENT_PART_COUNT] = [
        InstrumentPart::ViolinScroll,
        InstrumentPart::ViolinNut,
        InstrumentPart::ViolinBody,
        InstrumentPart::ViolinBridge,
        InstrumentPart::ViolinEndButton,
        InstrumentPart::StringAtNut(0),
        InstrumentPart::StringAtNut(1),
        InstrumentPart::StringAtNut(2),
        InstrumentPart::StringAtNut(3),
        InstrumentPart::StringAtBridge(0),
        InstrumentPart::StringAtBridge(1),
        InstrumentPart::StringAtBridge(2),
        InstrumentPart::StringAtBridge(3),
        InstrumentPart::BowFrog,
        InstrumentPart::BowTip,
        InstrumentPart::BowHairFrog,
        InstrumentPart::BowHairTip,
    ];

    /// Index in [`InstrumentPart::ALL`] (string numbers above 3 count as 3).
    ///
    /// ```
    /// use skeleton::InstrumentPart;
    /// for (i, p) in InstrumentPart::ALL.into_iter().enumerate() {
    ///     assert_eq!(p.index(), i);
    /// }
    /// ```
    pub fn index(self) -> usize {
        match self {
            InstrumentPart::ViolinScroll => 0,
            InstrumentPart::ViolinNut => 1,
            InstrumentPart::ViolinBody => 2,
            InstrumentPart::ViolinBridge => 3,
            InstrumentPart::ViolinEndButton => 4,
            InstrumentPart::StringAtNut(s) => 5 + usize::from(s.min(3)),
            InstrumentPart::StringAtBridge(s) => 9 + usize::from(s.min(3)),
            InstrumentPart::BowFrog => 13,
            InstrumentPart::BowTip => 14,
            InstrumentPart::BowHairFrog => 15,
            InstrumentPart::BowHairTip => 16,
        }
    }

    /// `true` for the bow's points, `false` for the violin's.
    pub fn is_bow(self) -> bool {
        self.index() >= InstrumentPart::BowFrog.index()
    }

    /// The stable name used in files.
    ///
    /// ```
    /// use skeleton::InstrumentPart;
    /// assert_eq!(InstrumentPart::StringAtBridge(3).name(), "string_e_bridge");
    /// assert_eq!(InstrumentPart::BowHairTip.name(), "bow_hair_tip");
    /// ```
    pub fn name(self) -> &'static str {
        const NUT: [&str; 4] = [
            "string_g_nut",
            "string_d_nut",
            "string_a_nut",
            "string_e_nut",
        ];
        const BRIDGE: [&str; 4] = [
            "string_g_bridge",
            "string_d_bridge",
            "string_a_bridge",
            "string_e_bridge",
        ];
        match self {
            InstrumentPart::ViolinScroll => "violin_scroll",
            InstrumentPart::ViolinNut => "violin_nut",
            InstrumentPart::ViolinBody => "violin_body",
            InstrumentPart::ViolinBridge => "violin_bridge",
            InstrumentPart::ViolinEndButton => "violin_end_button",
            InstrumentPart::StringAtNut(s) => NUT[usize::from(s.min(3))],
            InstrumentPart::StringAtBridge(s) => BRIDGE[usize::from(s.min(3))],
            InstrumentPart::BowFrog => "bow_frog",
            InstrumentPart::BowTip => "bow_tip",
            InstrumentPart::BowHairFrog => "bow_hair_frog",
            InstrumentPart::BowHairTip => "bow_hair_tip",
        }
    }
}

/// Pairs of instrument parts whose distance is fixed (the objects are rigid).
pub const INSTRUMENT_BONES: [(InstrumentPart, InstrumentPart); 6] = [
    (
        InstrumentPart::ViolinEndButton,
        InstrumentPart::ViolinScroll,
    ),
    (InstrumentPart::ViolinNut, InstrumentPart::ViolinBridge),
    (
        InstrumentPart::StringAtNut(0),
        InstrumentPart::StringAtBridge(0),
    ),
    (
        InstrumentPart::StringAtNut(3),
        InstrumentPart::StringAtBridge(3),
    ),
    (InstrumentPart::BowFrog, InstrumentPart::BowTip),
    (InstrumentPart::BowHairFrog, InstrumentPart::BowHairTip),
];
