"""Learning the commonsense tables from a corpus of (action, objects) records.

- :mod:`.corpus`: reading corpora (EPIC-KITCHENS folders, folders of Markdown recipes, ``action,objects`` CSV
  files) into records
- :mod:`.instructions`: (verb, objects) records from the clauses of recipe instructions, each object with its
  relation to the verb (object, place, means, source)
- :mod:`.archive`: the Open Recipe Archive read in place as a corpus
- :mod:`.synonyms`: folding corpus verbs into wecook's vocabulary (chop -> cut)
- :mod:`.nouns`: normalising and matching object names (shared with the runtime and the categories)
- :mod:`.learning`: counting P(A) and P(O | A)
- :mod:`.evaluation`: held-out verb prediction against a majority baseline
- :mod:`.roles`: how a clause names each noun (object, place, means, source, aside; a verb's particle)
- :mod:`.classes`: object classes and roles for backing off (EPIC's noun categories, wecook's categories)
- :mod:`.relations`: the role-aware model (relation:object features and their pairs, a tempered prior tuned on
  validation collections), measured on the held-out archive collections; not shipped
- :mod:`.logistic`, :mod:`.ensemble`: a logistic regression over the role-aware features, mixed with the naive
  Bayes of :mod:`.relations` (the mix picked on validation collections); not shipped
- :mod:`.build`: rebuilding ``wecook_core/assets/knowledge/`` (tables, derived categories, recipe records)
- :mod:`.report`: SOURCE.md (sources, licences, held-out figures per corpus)

The run-time side (loading the tables, ranking) is :mod:`wecook_core.knowledge.recognize`.
"""
