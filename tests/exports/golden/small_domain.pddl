(define (domain wecook)
  (:requirements :strips :typing)
  (:types agent thing - object
          tool container ingredient - thing)
  (:constants tabletop - container)
  (:predicates
    (free ?a - agent)
    (holding ?a - agent ?x - thing)
    (loose ?x - thing)
    (in ?x - thing ?c - thing)
    (received ?a - agent ?x - thing)
    (steadied ?x - thing)
    (done-cut ?x - thing)
    (done-peel ?x - thing)
    (done-stir ?x - thing)
    (done-pour ?x - thing)
    (done-sprinkle ?x - thing)
    (done-roll ?x - thing)
    (done-spread ?x - thing)
    (done-squeeze ?x - thing)
    (done-wrap ?x - thing)
    (done-dip ?x - thing)
    (done-transfer ?x - thing)
  )
  (:action grasp
    :parameters (?a - agent ?x - thing)
    :precondition (and (free ?a) (loose ?x))
    :effect (and (holding ?a ?x) (not (free ?a)) (not (loose ?x))))
  (:action release
    :parameters (?a - agent ?x - thing)
    :precondition (holding ?a ?x)
    :effect (and (free ?a) (loose ?x) (not (holding ?a ?x))))
  (:action cut
    :parameters (?a - agent ?t - thing ?x - thing)
    :precondition (holding ?a ?t)
    :effect (done-cut ?x))
  (:action cut-by-hand
    :parameters (?a - agent ?x - thing)
    :precondition (free ?a)
    :effect (done-cut ?x))
  (:action peel
    :parameters (?a - agent ?t - thing ?x - thing)
    :precondition (holding ?a ?t)
    :effect (done-peel ?x))
  (:action peel-by-hand
    :parameters (?a - agent ?x - thing)
    :precondition (free ?a)
    :effect (done-peel ?x))
  (:action stir
    :parameters (?a - agent ?t - thing ?x - thing)
    :precondition (holding ?a ?t)
    :effect (done-stir ?x))
  (:action stir-by-hand
    :parameters (?a - agent ?x - thing)
    :precondition (free ?a)
    :effect (done-stir ?x))
  (:action pour
    :parameters (?a - agent ?t - thing ?x - thing)
    :precondition (holding ?a ?t)
    :effect (done-pour ?x))
  (:action pour-by-hand
    :parameters (?a - agent ?x - thing)
    :precondition (free ?a)
    :effect (done-pour ?x))
  (:action sprinkle
    :parameters (?a - agent ?t - thing ?x - thing)
    :precondition (holding ?a ?t)
    :effect (done-sprinkle ?x))
  (:action sprinkle-by-hand
    :parameters (?a - agent ?x - thing)
    :precondition (free ?a)
    :effect (done-sprinkle ?x))
  (:action roll
    :parameters (?a - agent ?t - thing ?x - thing)
    :precondition (holding ?a ?t)
    :effect (done-roll ?x))
  (:action roll-by-hand
    :parameters (?a - agent ?x - thing)
    :precondition (free ?a)
    :effect (done-roll ?x))
  (:action spread
    :parameters (?a - agent ?t - thing ?x - thing)
    :precondition (holding ?a ?t)
    :effect (done-spread ?x))
  (:action spread-by-hand
    :parameters (?a - agent ?x - thing)
    :precondition (free ?a)
    :effect (done-spread ?x))
  (:action squeeze
    :parameters (?a - agent ?t - thing ?x - thing)
    :precondition (holding ?a ?t)
    :effect (done-squeeze ?x))
  (:action squeeze-by-hand
    :parameters (?a - agent ?x - thing)
    :precondition (free ?a)
    :effect (done-squeeze ?x))
  (:action wrap
    :parameters (?a - agent ?t - thing ?x - thing)
    :precondition (holding ?a ?t)
    :effect (done-wrap ?x))
  (:action wrap-by-hand
    :parameters (?a - agent ?x - thing)
    :precondition (free ?a)
    :effect (done-wrap ?x))
  (:action dip
    :parameters (?a - agent ?t - thing ?x - thing)
    :precondition (holding ?a ?t)
    :effect (done-dip ?x))
  (:action dip-by-hand
    :parameters (?a - agent ?x - thing)
    :precondition (free ?a)
    :effect (done-dip ?x))
  (:action transfer
    :parameters (?a - agent ?t - thing ?x - thing ?from - thing ?to - thing)
    :precondition (and (holding ?a ?t) (in ?x ?from))
    :effect (and (not (in ?x ?from)) (in ?x ?to) (done-transfer ?x)))
  (:action transfer-by-hand
    :parameters (?a - agent ?x - thing ?from - thing ?to - thing)
    :precondition (and (free ?a) (loose ?x) (in ?x ?from))
    :effect (and (not (in ?x ?from)) (in ?x ?to) (done-transfer ?x)))
  (:action handover
    :parameters (?g - agent ?r - agent ?x - thing)
    :precondition (and (holding ?g ?x) (free ?r))
    :effect (and (holding ?r ?x) (free ?g) (received ?r ?x) (not (holding ?g ?x)) (not (free ?r))))
  (:action hold-steady
    :parameters (?a - agent ?x - thing)
    :precondition (holding ?a ?x)
    :effect (steadied ?x))
)
