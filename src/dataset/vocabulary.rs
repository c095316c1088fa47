//! A scenario's object words: the kinds its videos show, the words that stand for several kinds,
//! and the attributes its objects carry beyond colour and kind.
//!
//! One [`Vocabulary`] per scenario (`dataset/<scenario>/vocabulary.rs`) is the single source of
//! these words: the scene API's `find` parses names with it, every scene object carries exactly
//! its attributes, and the prompt lists its kinds. Colour words are not here: every scenario
//! draws its colours from the release's one palette (`perception::palette`).
//!
//! Input: nothing (static data). Output: the words and the lookups `find` needs.

/// The words of one scenario.
#[derive(Debug, Clone, Copy)]
pub struct Vocabulary {
    /// Object kinds, singular, as questions name them and the prompt lists them, in the
    /// prompt's order (`cube`, `fixed point`). A kind may be two words.
    pub kinds: &'static [&'static str],
    /// Words that stand for several kinds (rope's `load`: a cube or a sphere).
    pub kind_groups: &'static [KindGroup],
    /// Attributes an object carries beyond colour and kind, in the order `find` reports them.
    pub attributes: &'static [Attribute],
    /// Words for objects the videos show but `find` never returns (a ball scene's ramps): they
    /// are understood, and find nothing.
    pub unfindable: &'static [&'static str],
    /// An attribute written as a trailing `(…)` after the words (rope's grid ids `(0 1)`).
    pub suffix: Option<Suffix>,
}

/// A word that stands for several kinds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct KindGroup {
    /// The word (`load`).
    pub word: &'static str,
    /// The kinds it matches (`cube`, `sphere`).
    pub kinds: &'static [&'static str],
}

/// One attribute of a scenario's objects and the words that set it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Attribute {
    /// Its name, which is also the `SceneObject` attribute programs read (`shape`).
    pub name: &'static str,
    /// What messages call several of its values (`pulley shapes`).
    pub plural: &'static str,
    /// Each word and the value it stands for (`little` → `solid`); the values are the words
    /// objects carry.
    pub words: &'static [(&'static str, &'static str)],
    /// The kind a name means when it gives this attribute but no kind (`hollow` → `pulley`).
    pub implies_kind: Option<&'static str>,
    /// Whether the value is part of an object's short name, between colour and kind (`blue
    /// solid pulley`).
    pub in_name: bool,
}

/// An attribute written as `(…)` after the words of a name.
#[derive(Debug, Clone, Copy)]
pub struct Suffix {
    /// The attribute it sets (`grid`).
    pub attribute: &'static str,
    /// Its form in messages (`(layer column)`).
    pub form: &'static str,
    /// An example (`(0 1)`).
    pub example: &'static str,
    /// Reads the text between the parentheses into the attribute's value (`0 1`); `None` when
    /// it is not of the form.
    pub parse: fn(&str) -> Option<String>,
}

impl Vocabulary {
    /// Whether `word` is one of this scenario's kinds.
    pub fn has_kind(&self, word: &str) -> bool {
        self.kinds.contains(&word)
    }

    /// The kinds `word` stands for, when it is a group word.
    pub fn group(&self, word: &str) -> Option<&'static [&'static str]> {
        self.kind_groups
            .iter()
            .find(|group| group.word == word)
            .map(|group| group.kinds)
    }

    /// The attribute `word` sets and its value (`little` → `shape`, `solid`).
    pub fn attribute_word(&self, word: &str) -> Option<(&'static Attribute, &'static str)> {
        let attributes: &'static [Attribute] = self.attributes;
        attributes.iter().find_map(|attribute| {
            attribute
                .words
                .iter()
                .find(|(spelling, _)| *spelling == word)
                .map(|(_, value)| (attribute, *value))
        })
    }

    /// The attribute called `name`.
    pub fn attribute(&self, name: &str) -> Option<&'static Attribute> {
        let attributes: &'static [Attribute] = self.attributes;
        attributes.iter().find(|attribute| attribute.name == name)
    }

    /// Every word that names an object of this scenario: kinds, group words and unfindable
    /// objects.
    pub fn object_words(&self) -> impl Iterator<Item = &'static str> + '_ {
        let kinds: &'static [&'static str] = self.kinds;
        let unfindable: &'static [&'static str] = self.unfindable;
        kinds
            .iter()
            .copied()
            .chain(self.kind_groups.iter().map(|group| group.word))
            .chain(unfindable.iter().copied())
    }
}
