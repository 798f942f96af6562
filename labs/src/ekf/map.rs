use crate::Error;
use nalgebra::Vector2;
use serde::{Deserialize, Serialize};

/// A landmark: its id as the data files name it, and its position in metres.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Landmark {
    pub id: u32,
    pub position: Vector2<f64>,
}

/// The landmark map. Landmarks keep the order of the map file; the filter's association
/// `c` is an index into that order (0-based), not an id.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "Vec<Landmark>", into = "Vec<Landmark>")]
pub struct Map {
    landmarks: Vec<Landmark>,
}

impl Map {
    /// A map of at least one landmark, ids unique, positions finite.
    pub fn new(landmarks: Vec<Landmark>) -> Result<Self, Error> {
        if landmarks.is_empty() {
            return Err(Error::invalid("map", "the map has no landmarks"));
        }
        for (i, landmark) in landmarks.iter().enumerate() {
            if !landmark.position.iter().all(|v| v.is_finite()) {
                return Err(Error::invalid(
                    "map",
                    format!("landmark {} has a position that is not finite", landmark.id),
                ));
            }
            if landmarks[..i].iter().any(|other| other.id == landmark.id) {
                return Err(Error::invalid(
                    "map",
                    format!("landmark id {} appears twice", landmark.id),
                ));
            }
        }
        Ok(Map { landmarks })
    }

    pub fn landmarks(&self) -> &[Landmark] {
        &self.landmarks
    }

    pub fn len(&self) -> usize {
        self.landmarks.len()
    }

    pub fn is_empty(&self) -> bool {
        self.landmarks.is_empty()
    }

    /// The index of the landmark with this id.
    pub fn index_of(&self, id: u32) -> Option<usize> {
        self.landmarks.iter().position(|landmark| landmark.id == id)
    }

    /// The ids, compressed into ranges for messages: "1-9, 11, 13-14".
    pub fn describe_ids(&self) -> String {
        let mut ids: Vec<u32> = self.landmarks.iter().map(|l| l.id).collect();
        ids.sort_unstable();
        let mut parts: Vec<String> = Vec::new();
        let mut start = 0;
        for i in 1..=ids.len() {
            if i == ids.len() || ids[i] != ids[i - 1] + 1 {
                parts.push(match i - 1 - start {
                    0 => ids[start].to_string(),
                    _ => format!("{}-{}", ids[start], ids[i - 1]),
                });
                start = i;
            }
        }
        parts.join(", ")
    }
}

impl TryFrom<Vec<Landmark>> for Map {
    type Error = Error;
    fn try_from(landmarks: Vec<Landmark>) -> Result<Self, Error> {
        Map::new(landmarks)
    }
}

impl From<Map> for Vec<Landmark> {
    fn from(map: Map) -> Self {
        map.landmarks
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn landmark(id: u32) -> Landmark {
        Landmark {
            id,
            position: Vector2::new(f64::from(id), 0.0),
        }
    }

    #[test]
    fn rejects_empty_maps_and_repeated_ids() {
        assert!(
            Map::new(vec![])
                .unwrap_err()
                .to_string()
                .contains("no landmarks")
        );
        let err = Map::new(vec![landmark(1), landmark(2), landmark(1)]).unwrap_err();
        assert_eq!(err.to_string(), "map: landmark id 1 appears twice");
    }

    #[test]
    fn finds_indices_and_describes_ids() {
        let map = Map::new(
            [1, 2, 3, 4, 5, 6, 7, 8, 9, 11, 13, 14]
                .map(landmark)
                .to_vec(),
        )
        .unwrap();
        assert_eq!(map.index_of(11), Some(9));
        assert_eq!(map.index_of(10), None);
        assert_eq!(map.describe_ids(), "1-9, 11, 13-14");
    }
}
