//! The mark a bench limits file leaves on an object whose limits it tightened: which side
//! (maximum, minimum) the bench now decides and which file says so, so that a refused
//! value names the bench limit and its file instead of the dictionary's range. Pure data.

/// Which of an object's limits come from the bench, and from which file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BenchCap {
    /// `limits file /x/drivescript-limits.yaml` (with how it was found when that helps).
    pub origin: String,
    /// The object's `max` is the bench's cap.
    pub max: bool,
    /// The object's `min` is the bench's negative cap.
    pub min: bool,
}
