//! The question engine: generates ContPhy questions from annotations (rope only; the other
//! scenarios' engines are not public).
